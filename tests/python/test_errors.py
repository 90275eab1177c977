# Bad input raises ValueError/TypeError with a one-line message (the CLI's, where the CLI has one),
# never a crash and never a NaN returned silently.
import numpy as np
import pytest

import ganzfeld


@pytest.mark.parametrize("spec", ["specular:alpha=-1", "nosuchmodel", "specular:alpha=8,beta=2", "specular:alpha=",
                                  "0.7*lambert + ", "ggx:alpha=0", "minnaert:xi=nan", "lambert\n+x"])
def test_bad_specs_raise_the_cli_message(cli, spec):
    expected = cli.refusal("eval", "--model", spec, "--law", "h", "--theta-j", "10")
    with pytest.raises(ValueError) as raised:
        ganzfeld.Model(spec)
    assert str(raised.value) == expected
    assert "\n" not in str(raised.value)


def test_spec_must_be_text():
    with pytest.raises(TypeError, match="spec must be a str"):
        ganzfeld.Model(8)


def test_tolerance_and_budget_messages_match_the_cli(cli):
    model = ganzfeld.Model("specular:alpha=8")
    for tol in [0.0, 1e-16, 2.0, float("nan"), float("inf")]:
        expected = cli.refusal("eval", "--model", "specular:alpha=8", "--law", "h", "--theta-j", "10", "--tol", tol)
        with pytest.raises(ValueError) as raised:
            model.h(theta_j=10, tol=tol)
        assert str(raised.value) == expected.replace("--tol ", "tol=")  # one refusal, each front end's spelling
    expected = cli.refusal("eval", "--model", "specular:alpha=8", "--law", "h", "--theta-j", "10", "--max-evals", 10)
    with pytest.raises(ValueError) as raised:
        model.h(theta_j=10, max_evals=10)
    assert str(raised.value) == expected.replace("--max-evals ", "max_evals=")


@pytest.mark.parametrize("call, error, message", [
    (lambda m: m.g([1, 0], [0, 0, 1]), ValueError, r"^i has shape \(2,\); expected \(\.\.\., 3\)"),
    (lambda m: m.g(np.ones((4, 2)), [0, 0, 1]), ValueError, r"^i has shape \(4, 2\)"),
    (lambda m: m.g(5.0, [0, 0, 1]), ValueError, r"^i has shape \(\)"),
    (lambda m: m.g("up", [0, 0, 1]), TypeError, r"^i must be real numbers"),
    (lambda m: m.g([1j, 0, 1], [0, 0, 1]), TypeError, r"^i must be real numbers"),
    (lambda m: m.g([[0, 0, 1], [np.nan, 0, 1]], [0, 0, 1]), ValueError,
     r"^i\[1\] = \[nan, 0\.0, 1\.0\] is not a direction; expected three finite numbers X,Y,Z$"),
    (lambda m: m.g([0, 0, 1], [[[0, 0, 1], [0, np.inf, 1]]]), ValueError, r"^j\[0, 1\] = \[0\.0, inf, 1\.0\]"),
    (lambda m: m.g([0, 0, 0], [0, 0, 1]), ValueError, r"^i = \[0\.0, 0\.0, 0\.0\] has zero length"),
    (lambda m: m.g([1e-200, 0, 0], [0, 0, 1]), ValueError, r"has zero length"),
    (lambda m: m.g([1e200, 1e200, 0], [0, 0, 1]), ValueError, r"has zero length"),
    (lambda m: m.g([0, 0, 1], [0, 0.5, -1]), ValueError,
     r"^j = \[0\.0, 0\.5, -1\.0\] is below the surface; allowed: j·n >= 0$"),
    (lambda m: m.a([0, 0.5, -1]), ValueError, r"^i = .* is below the surface; allowed: i·n >= 0$"),
    (lambda m: m.g(np.ones((4, 3)), np.ones((5, 3))), ValueError,
     r"^i of shape \(4, 3\) and j of shape \(5, 3\) do not broadcast"),
    (lambda m: m.g(theta_i=[10, 190], theta_j=10), ValueError,
     r"^theta_i\[1\] = 190\.0 is out of range; allowed: \[0, 180\] degrees$"),
    (lambda m: m.a(theta_i=100), ValueError, r"^theta_i = 100\.0 is out of range; allowed: \[0, 90\] degrees$"),
    (lambda m: m.h(theta_j=np.nan), ValueError, r"^theta_j = nan is out of range"),
    (lambda m: m.h(cos_theta_j=-0.5), ValueError, r"^cos_theta_j = -0\.5 is out of range; allowed: \[0, 1\]$"),
    (lambda m: m.g(theta_i=10, theta_j=10, phi=np.inf), ValueError,
     r"^phi = inf is out of range; allowed: a finite number"),
    (lambda m: m.g(i=[0, 0, 1], theta_i=10, theta_j=10), ValueError,
     r"^give one of i=, theta_i=, cos_theta_i=; got i=, theta_i=$"),
    (lambda m: m.g(theta_j=10), ValueError, r"^law g needs the incident direction"),
    (lambda m: m.g(theta_i=10), ValueError, r"^law g needs the view direction"),
    (lambda m: m.g([0, 0, 1], [0, 0, 1], phi=10), ValueError, r"^phi= goes with theta_j="),
    (lambda m: m.g([0, 0, 1], [0, 0, 1], progress=3), TypeError, r"^progress must be None, True or a callable"),
])
def test_bad_directions_raise(call, error, message):
    with pytest.raises(error, match=message):
        call(ganzfeld.Model("specular:alpha=8"))


def test_valid_input_gives_finite_values():
    model = ganzfeld.Model("0.5*backscatter:alpha=1 + 0.5*asperity:alpha=1")
    rng = np.random.default_rng(5)
    i = rng.normal(size=(64, 3))
    j = np.abs(rng.normal(size=(64, 3)))
    j[:8, 2] = 0.0  # grazing views
    g = model.g(i, j, tol=1e-7)
    assert np.all(np.isfinite(g.value)) and np.all(np.isfinite(g.error))
    assert np.all(np.isfinite(model.f(np.abs(i), j)))


def test_table_refusals(cli, tmp_path):
    model = ganzfeld.Model("specular:alpha=8")
    with pytest.raises(ValueError, match=r"^law 'f' has no table"):
        ganzfeld.bake(model, "f", res=8)
    with pytest.raises(ValueError, match=r"^res= and max_error= are mutually exclusive"):
        ganzfeld.bake(model, "g", res=8, max_error=1e-3)
    with pytest.raises(ValueError, match=r"^bake needs res="):
        ganzfeld.bake(model, "g")
    with pytest.raises(ValueError, match=r"^frame= cannot be combined with max_error="):
        ganzfeld.bake(model, "g", max_error=1e-3, frame="lobe")
    with pytest.raises(ValueError, match=r"^max_bytes= needs max_error="):
        ganzfeld.bake(model, "g", res=8, max_bytes=1000)
    with pytest.raises(TypeError, match=r"^res must be"):
        ganzfeld.bake(model, "g", res=8.5)
    # The library's own messages, as the command line prints them:
    expected = cli.refusal("bake", "--model", "specular:alpha=8", "--law", "g", "--res", "8x1x8",
                           "-o", tmp_path / "x.exr")
    with pytest.raises(ValueError) as raised:
        ganzfeld.bake(model, "g", res="8x1x8")
    assert str(raised.value) == expected.replace("--res ", "res=")  # one refusal, each front end's spelling
    expected = cli.refusal("bake", "--model", "specular:alpha=8", "--law", "g", "--res", "8", "--encoding", "fp8",
                           "-o", tmp_path / "x.exr")
    with pytest.raises(ValueError) as raised:
        ganzfeld.bake(model, "g", res=8, encoding="fp8")
    assert str(raised.value) == expected
    missing = tmp_path / "missing.exr"
    with pytest.raises(ValueError) as raised:
        ganzfeld.read(missing)
    assert str(raised.value) == cli.refusal("info", missing)
    garbage = tmp_path / "garbage.exr"
    garbage.write_bytes(b"not a table at all")
    with pytest.raises(ValueError) as raised:
        ganzfeld.read(garbage)
    assert str(raised.value) == cli.refusal("info", garbage)
