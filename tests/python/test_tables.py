# Tables: the same files and lookup as the command line (bake, info, sample), both ways round.
import numpy as np
import pytest

import ganzfeld
from conftest import vector_text

SPEC = "specular:alpha=8"


def lookups(cli, path, table, pairs):
    """Each pair looked up by `ganzfeld sample --json` and by Table.sample: identical documents."""
    for i, j in pairs:
        flags = {"g": ["--i", vector_text(i), "--j", vector_text(j)], "h": ["--j", vector_text(j)],
                 "a": ["--i", vector_text(i)]}[table.law]
        doc = cli.json("sample", path, *flags)
        ours = table.sample(*{"g": (i, j), "h": (j,), "a": (i,)}[table.law])
        assert ours == table.sample(**{"g": {"i": i, "j": j}, "h": {"j": j}, "a": {"i": i}}[table.law])
        assert float(ours.value) == doc["value"]
        assert float(ours.error) == doc["error"]
        assert float(ours.node_error) == doc["node_error"]


def pairs(count, seed):
    rng = np.random.default_rng(seed)
    i = rng.normal(size=(count, 3))
    j = np.abs(rng.normal(size=(count, 3)))
    return list(zip(i, j))


def test_python_table_reads_in_the_cli(cli, tmp_path):
    table = ganzfeld.bake(SPEC, "g", res=(9, 8, 5), tol=1e-8, interpolation="catmull-rom")
    assert table.values.shape == (9, 8, 5) and table.errors.shape == (9, 8, 5)
    assert table.values.dtype == np.float32 and not table.values.flags.writeable
    assert table.path is None and table.frame == "cosines" and table.interpolation == "catmull-rom"
    path = tmp_path / "g.exr"
    table.write(path)
    assert table.path == str(path)
    info = cli.json("info", path)
    assert info == table.info
    assert info["command"].startswith("python: ganzfeld.bake('specular:alpha=8', 'g', res='9x8x5'")
    g = np.abs(pairs(1, 0)[0][0])
    i_below = -g
    lookups(cli, path, table, pairs(4, 1) + [(i_below, g)])


def test_cli_table_reads_in_python(cli, tmp_path):
    path = tmp_path / "h.exr"
    code, _, err = cli.run("bake", "--model", SPEC, "--law", "h", "--res", "17", "--tol", "1e-8", "-o", path)
    assert code == 0, err
    table = ganzfeld.read(path)
    assert table.law == "h" and table.model == SPEC and table.path == str(path)
    ours = ganzfeld.bake(SPEC, "h", res=17, tol=1e-8)  # the same options bake the same numbers
    assert np.array_equal(table.values, ours.values) and np.array_equal(table.errors, ours.errors)
    assert table.lookup_error == ours.lookup_error
    lookups(cli, path, table, pairs(4, 2))
    # a table of the lobe frame, baked to a lookup error by the command line
    path = tmp_path / "g.exr"
    code, _, err = cli.run("bake", "--model", SPEC, "--law", "g", "--max-error", "3e-3", "-o", path)
    assert code == 0, err
    table = ganzfeld.read(path)
    assert table.lookup_error <= 3e-3 and table.info["target_error"] == 3e-3
    lookups(cli, path, table, pairs(4, 3))


def test_max_error_bake_matches_the_cli(cli, tmp_path):
    path = tmp_path / "a.exr"
    code, _, err = cli.run("bake", "--model", SPEC, "--law", "a", "--max-error", "1e-4", "-o", path)
    assert code == 0, err
    theirs = ganzfeld.read(path)
    ours = ganzfeld.bake(SPEC, "a", max_error=1e-4)
    assert ours.axes == theirs.axes and ours.interpolation == theirs.interpolation
    assert np.array_equal(ours.values, theirs.values)
    assert ours.lookup_error == theirs.lookup_error <= 1e-4


def test_lookup_within_its_stated_error():
    """Lookups at fresh points differ from the law's cubature by no more than lookup_error (+ the
    cubature's own error): the table's headline bound, validated at bake time."""
    model = ganzfeld.Model(SPEC)
    table = ganzfeld.bake(model, "g", res=(17, 17, 9), tol=1e-9, checks=500)
    rng = np.random.default_rng(9)
    i = rng.normal(size=(200, 3))
    j = np.abs(rng.normal(size=(200, 3)))
    lookup = table.sample(i, j)
    exact = model.g(i, j, tol=1e-10)
    assert lookup.value.shape == (200,)
    covered = np.abs(lookup.value - exact.value) <= lookup.error + exact.error
    assert covered.mean() >= 0.99  # tests/tables_test.cpp: the bound holds at >= 99.9% of fresh points
    assert lookup.error[0] == table.lookup_error


def test_sample_takes_angles():
    table = ganzfeld.bake(SPEC, "g", res=(5, 5, 3), tol=1e-7)
    by_angles = table.sample(theta_i=[30, 60], theta_j=45, phi=90)
    i = [[np.sin(np.radians(t)), 0, np.cos(np.radians(t))] for t in (30, 60)]
    j = [np.sin(np.radians(45)) * np.cos(np.radians(90)), np.sin(np.radians(45)) * np.sin(np.radians(90)),
         np.cos(np.radians(45))]
    assert by_angles.value == pytest.approx(table.sample(i, j).value, abs=1e-12)
