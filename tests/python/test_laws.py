# model.f/g/h/a/r: the same numbers as `ganzfeld eval --json`, bit for bit, broadcast like numpy.
import math

import numpy as np
import pytest

import ganzfeld
from conftest import vector_text

MODELS = ["specular:alpha=8", "0.7*minnaert:xi=1 + 0.3*specular:alpha=8", "ggx:alpha=0.3"]
TOL = 1e-8  # loose enough to keep the CLI's per-point processes quick; any tolerance must agree


def random_pairs(count, seed, sky=True):
    """`count` (i, j) pairs, not unit length (both sides normalize), i below the horizon for g."""
    rng = np.random.default_rng(seed)
    i = rng.normal(size=(count, 3)) * rng.uniform(0.5, 3.0, size=(count, 1))
    j = rng.normal(size=(count, 3))
    j[:, 2] = np.abs(j[:, 2])
    if not sky:
        i[:, 2] = np.abs(i[:, 2])
    return i, j


def assert_same_as_cli(estimate, doc):
    assert float(estimate.value) == doc["value"]
    assert float(estimate.error) == doc["error"]
    assert int(estimate.evaluations) == doc["evaluations"]
    assert bool(estimate.converged) == doc["converged"]


@pytest.mark.parametrize("spec", MODELS)
def test_g_equals_cli_bit_for_bit(cli, spec):
    model = ganzfeld.Model(spec)
    i, j = random_pairs(4, seed=1)
    batch = model.g(i, j, tol=TOL)
    for k in range(len(i)):
        doc = cli.json("eval", "--model", spec, "--law", "g", "--i", vector_text(i[k]), "--j", vector_text(j[k]),
                       "--tol", TOL)
        assert doc["model"] == model.spec
        assert_same_as_cli(ganzfeld.Estimate(*(a[k] for a in batch)), doc)


def test_angles_equal_cli_bit_for_bit(cli):
    model = ganzfeld.Model("specular:alpha=8")
    rng = np.random.default_rng(7)
    odd = zip(rng.uniform(0, 180, 6), rng.uniform(0, 90, 6), rng.uniform(-360, 360, 6))
    for theta_i, theta_j, phi in [(60, 30, 180), (135, 80, 45), (0, 0, 0), (180, 90, 10), *odd]:
        doc = cli.json("eval", "--model", model.spec, "--law", "g", "--theta-i", theta_i, "--theta-j", theta_j,
                       "--phi", phi, "--tol", TOL)
        assert_same_as_cli(model.g(theta_i=theta_i, theta_j=theta_j, phi=phi, tol=TOL), doc)
        assert model.g(theta_i=theta_i, theta_j=theta_j, phi=phi, tol=TOL).value.shape == ()


@pytest.mark.parametrize("law", ["f", "h", "a", "r"])
def test_other_laws_equal_cli_bit_for_bit(cli, law):
    spec = MODELS[1]
    model = ganzfeld.Model(spec)
    i, j = random_pairs(3, seed=2, sky=False)
    for k in range(len(i)):
        flags = {"f": ["--i", vector_text(i[k]), "--j", vector_text(j[k])], "h": ["--j", vector_text(j[k])],
                 "a": ["--i", vector_text(i[k])], "r": []}[law]
        doc = cli.json("eval", "--model", spec, "--law", law, *flags, "--tol", TOL)
        if law == "f":
            assert float(model.f(i[k], j[k])) == doc["value"]
        elif law == "h":
            assert_same_as_cli(model.h(j[k], tol=TOL), doc)
        elif law == "a":
            assert_same_as_cli(model.a(i[k], tol=TOL), doc)
        else:
            assert_same_as_cli(model.r(tol=TOL), doc)
            break


def test_broadcasting_shapes_and_entries():
    model = ganzfeld.Model("specular:alpha=8")
    i, _ = random_pairs(5, seed=3)
    _, j = random_pairs(4, seed=4)
    grid = model.g(i[:, None, :], j[None, :, :], tol=TOL)
    for a in grid:
        assert a.shape == (5, 4)
    assert grid.evaluations.dtype == np.int64 and grid.converged.dtype == np.bool_
    for p in range(5):
        for q in range(4):  # every entry is the integral of its own pair, whatever the batch
            single = model.g(i[p], j[q], tol=TOL)
            assert grid.value[p, q] == single.value and grid.error[p, q] == single.error
    # angles broadcast against each other like numpy: theta_i (3, 1) x theta_j (2,) x phi ()
    angles = model.g(theta_i=np.array([[10.0], [60.0], [120.0]]), theta_j=[20.0, 70.0], phi=30.0, tol=TOL)
    assert angles.value.shape == (3, 2)
    assert angles.value[2, 1] == model.g(theta_i=120, theta_j=70, phi=30, tol=TOL).value
    assert model.h(cos_theta_j=np.linspace(0, 1, 7).reshape(7, 1), tol=TOL).value.shape == (7, 1)
    assert model.f(theta_i=[[10.0, 20.0]], theta_j=45).shape == (1, 2)
    assert model.g(np.zeros((0, 3)) + [0, 0, 1], [0, 0, 1]).value.shape == (0,)


def test_known_values():
    """White Lambert: g = (1 + i·n)/2 and h = a = r = 1 (K&P); cosine keywords give the same as angles."""
    lambert = ganzfeld.Model("lambert")
    cos_i = np.linspace(-1, 1, 9)
    g = lambert.g(cos_theta_i=cos_i, theta_j=40, tol=1e-12)
    assert np.all(np.abs(g.value - (1 + cos_i) / 2) <= g.error + 1e-15)
    assert np.all(g.converged)
    assert abs(lambert.h(theta_j=[0, 45, 89.9], tol=1e-12).value - 1).max() < 1e-12
    assert abs(lambert.r(tol=1e-12).value - 1) < 1e-12
    assert lambert.f([0, 0, 1], [0, 0, 1]) == pytest.approx(1 / math.pi, rel=1e-15)


def test_models_and_traits_equal_cli(cli):
    assert ganzfeld.models() == cli.json("models")
    model = ganzfeld.Model("0.5*specular:alpha=8+0.5*lambert")
    assert model.traits == {"isotropic": True, "reciprocal": True, "energy_class": "plausible"}
    assert ganzfeld.Model(model.spec).spec == model.spec  # the canonical spec parses back to itself


def test_verify_equals_cli(cli):
    ours = ganzfeld.verify()
    code, out, err = cli.run("verify", "--json")
    import json
    assert json.loads(out) == ours
    assert ours["passed"] is True and code == 0


def test_the_closed_form_example_runs(tmp_path):
    """examples/verify_closed_form.py, as a user runs it: K&P's printed g of Minnaert xi = 1 holds."""
    import pathlib
    import subprocess
    import sys
    example = pathlib.Path(__file__).resolve().parents[2] / "examples" / "verify_closed_form.py"
    out = subprocess.run([sys.executable, str(example)], capture_output=True, text=True, cwd=tmp_path)
    assert out.returncode == 0, out.stderr
    assert "largest |mine - ganzfeld| = " in out.stdout
    largest = float(out.stdout.split("largest |mine - ganzfeld| = ")[1].split(",")[0])
    assert largest < 1e-11
