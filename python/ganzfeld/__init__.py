"""Koenderink & Pont's laws of any BRDF, from Python, with an error estimate beside every value.

J. J. Koenderink & S. C. Pont, "Material Properties and Extended Sources for Surface Rendering"
(K&P below) render a convex object under three canonical light fields exactly from:

- f(i, j), the BRDF, "Law of Shading" (section "Collimated beam");
- g(i, j) = ∫_{k·n>0, k·i>0} (k·n) f(k, j) dk, the "Law of Vignetting": a uniform sky with pole i,
  i·n in [-1, 1] (section "Hemispherical diffuse beam");
- h(j) = ∫_{k·n>0} (k·n) f(k, j) dk, the "Law of Darkening" (section "Fully diffuse beam: Ganzfeld");
- a(i) = ∫_{j·n>0} (j·n) f(i, j) dj, the albedo, and r = (1/π) ∫ (i·n) a(i) di, the double-diffuse
  reflectance (same section).

Directions are in the local frame, n = +z; i points to the source (the sky's pole for g), j to the
eye. Every law is integrated by the library's adaptive cubature (integrate/laws.h) and returns an
`Estimate`: value, error estimate, evaluations and whether the tolerance was met. Arrays broadcast
like numpy; the work runs in C++ on every core with the GIL released; Ctrl-C interrupts it.
Each value equals what `ganzfeld eval --json` prints for the same arguments, bit for bit.
See docs/python.md.
"""

from __future__ import annotations

import os
import sys
from typing import Any, Callable, NamedTuple, Optional, Union

try:
    import numpy as np

    from . import _core
except ImportError as missing:  # another interpreter than the one the extension was built for
    from ._built_for import INTERPRETER

    raise ImportError(f"ganzfeld was built for {INTERPRETER}, not {sys.executable} ({missing}); run that "
                      "interpreter (scripts/python runs it with build/python on the path)") from missing

__version__: str = _core.__version__

__all__ = ["Estimate", "Lookup", "Model", "Table", "bake", "models", "read", "verify"]

#: The cubature's default absolute tolerance, as `ganzfeld eval --tol` (integrate/cubature.h).
DEFAULT_TOL: float = _core.DEFAULT_TOL
#: The default evaluation budget per integral, as `ganzfeld eval --max-evals`.
DEFAULT_MAX_EVALS: int = _core.DEFAULT_MAX_EVALS

Progress = Union[None, bool, Callable[[int, int], Any]]
ArrayLike = Any


class Estimate(NamedTuple):
    """Values of a law with what the cubature says about them, each shaped like the directions.

    `error` is the engine's estimate of |value - law|, meant to bound it (docs/performance.md and
    docs/reliability-genz.md measure how often it does); `converged` is False where the tolerance was
    not met within the evaluation budget (the value and its larger error are still returned).
    """

    value: Any
    error: Any
    evaluations: Any
    converged: Any


class Lookup(NamedTuple):
    """A table lookup: `value`, `error` (the table's validated lookup error: a bound of
    |lookup - law| anywhere in the domain, docs/lut-format.md) and `node_error` (the blend of the
    stored per-node errors used here; it leaves out the interpolation between nodes)."""

    value: Any
    error: Any
    node_error: Any


def models() -> dict:
    """The registry, as `ganzfeld models --json` prints it: {"models": [{name, summary, source,
    example, parameters (name, type, min, max, default, meaning, allowed, ...), isotropic,
    reciprocal, energy_class, closed_forms}], "mixtures": ...}."""
    return _core.models_json()


def verify() -> dict:
    """Every closed form the papers print, checked against cubature: the document of
    `ganzfeld verify --json` ({"checks": [...], "agreement", "passed"}; docs/errata.md)."""
    return _core.verify_json()


# --- directions ---------------------------------------------------------------------------------


def _numbers(name: str, x: ArrayLike) -> np.ndarray:
    a = np.asarray(x)
    if a.dtype == object or a.dtype.kind not in "biuf":
        raise TypeError(f"{name} must be real numbers; got {type(x).__name__} of dtype {a.dtype}")
    return a.astype(np.float64, copy=False)


def _index(name: str, a: np.ndarray, flat: int, batch_shape: tuple) -> str:
    if not batch_shape:
        return name
    where = np.unravel_index(flat, batch_shape)
    return f"{name}[{', '.join(str(int(k)) for k in where)}]"


def _vector_text(v: np.ndarray) -> str:
    return "[" + ", ".join(repr(float(x)) for x in v) + "]"


def _vectors(name: str, x: ArrayLike, allow_below: bool) -> np.ndarray:
    """Directions X,Y,Z of shape (..., 3), checked and normalized as `ganzfeld eval` checks and
    normalizes --i/--j (cli/args.cpp): finite, nonzero, above the surface unless allowed."""
    a = _numbers(name, x)
    if a.ndim == 0 or a.shape[-1] != 3:
        raise ValueError(f"{name} has shape {a.shape}; expected (..., 3): directions X,Y,Z in the local frame (n = +z)")
    batch = a.shape[:-1]
    rows = a.reshape(-1, 3)
    with np.errstate(over="ignore", under="ignore", invalid="ignore"):  # |d| overflowing to inf is refused below
        length = np.sqrt(np.sum(rows * rows, axis=-1))
    finite = np.all(np.isfinite(rows), axis=-1)
    for bad, why in ((~finite, "is not a direction; expected three finite numbers X,Y,Z"),
                     (~((length > 0) & np.isfinite(length)), "has zero length; expected a nonzero direction X,Y,Z"),
                     (rows[:, 2] < 0 if not allow_below else np.zeros(len(rows), bool),
                      f"is below the surface; allowed: {name}·n >= 0")):
        if bad.any():
            k = int(np.argmax(bad))
            raise ValueError(f"{_index(name, a, k, batch)} = {_vector_text(rows[k])} {why}")
    return _core.unit(np.ascontiguousarray(rows)).reshape(batch + (3,))


def _range(name: str, x: ArrayLike, lo: float, hi: float, unit: str) -> np.ndarray:
    a = _numbers(name, x)
    flat = a.reshape(-1)
    bad = ~(np.isfinite(flat) & (flat >= lo) & (flat <= hi))
    if bad.any():
        k = int(np.argmax(bad))
        allowed = f"a finite number of{unit}" if np.isinf(lo) else f"[{lo:g}, {hi:g}]{unit}"
        raise ValueError(f"{_index(name, a, k, a.shape)} = {float(flat[k])!r} is out of range; allowed: {allowed}")
    return a


def _from_angles(theta: Optional[np.ndarray], cos_theta: Optional[np.ndarray], phi: np.ndarray) -> np.ndarray:
    source = theta if theta is not None else cos_theta
    shape = np.broadcast_shapes(source.shape, phi.shape)
    s = np.ascontiguousarray(np.broadcast_to(source, shape).reshape(-1))
    p = np.ascontiguousarray(np.broadcast_to(phi, shape).reshape(-1))
    rows = _core.directions(s, p, theta is not None)
    return rows.reshape(shape + (3,))


def _incident(law: str, i, theta_i, cos_theta_i) -> np.ndarray:
    """i from i= (X,Y,Z), theta_i= (degrees from n) or cos_theta_i=, at azimuth 0; below the
    surface only for g (the sky's pole)."""
    given = [name for name, v in (("i", i), ("theta_i", theta_i), ("cos_theta_i", cos_theta_i)) if v is not None]
    if len(given) > 1:
        raise ValueError(f"give one of i=, theta_i=, cos_theta_i=; got {', '.join(n + '=' for n in given)}")
    if not given:
        raise ValueError(f"law {law} needs the incident direction: give i=X,Y,Z, theta_i=DEG or cos_theta_i=C")
    sky = law == "g"
    if i is not None:
        return _vectors("i", i, allow_below=sky)
    zero = np.zeros(())
    if theta_i is not None:
        return _from_angles(_range("theta_i", theta_i, 0, 180 if sky else 90, " degrees"), None, zero)
    return _from_angles(None, _range("cos_theta_i", cos_theta_i, -1 if sky else 0, 1, ""), zero)


def _outgoing(law: str, j, theta_j, cos_theta_j, phi) -> np.ndarray:
    """j from j= (X,Y,Z), or theta_j= (degrees) or cos_theta_j= with phi= (degrees, the azimuth
    of j minus that of i), above the surface."""
    given = [name for name, v in (("j", j), ("theta_j", theta_j), ("cos_theta_j", cos_theta_j)) if v is not None]
    if len(given) > 1:
        raise ValueError(f"give one of j=, theta_j=, cos_theta_j=; got {', '.join(n + '=' for n in given)}")
    if not given:
        raise ValueError(f"law {law} needs the view direction: give j=X,Y,Z, or theta_j=DEG or cos_theta_j=C "
                         "[with phi=DEG]")
    if j is not None:
        if phi is not None:
            raise ValueError("phi= goes with theta_j= or cos_theta_j=; a vector j= carries its own azimuth")
        return _vectors("j", j, allow_below=False)
    p = np.zeros(()) if phi is None else _range("phi", phi, -np.inf, np.inf, " degrees")
    if theta_j is not None:
        return _from_angles(_range("theta_j", theta_j, 0, 90, " degrees"), None, p)
    return _from_angles(None, _range("cos_theta_j", cos_theta_j, 0, 1, ""), p)


def _pairs(i: np.ndarray, j: np.ndarray, names=("i", "j")) -> tuple:
    """Broadcast (..., 3) directions against each other: contiguous (N, 3) rows and the shape."""
    try:
        shape = np.broadcast_shapes(i.shape[:-1], j.shape[:-1])
    except ValueError:
        raise ValueError(f"{names[0]} of shape {i.shape} and {names[1]} of shape {j.shape} do not broadcast "
                         "(numpy's rules, over all axes but the last)") from None
    rows = [np.ascontiguousarray(np.broadcast_to(d, shape + (3,)).reshape(-1, 3)) for d in (i, j)]
    return rows[0], rows[1], shape


def _shaped(a: np.ndarray, shape: tuple):
    out = a.reshape(shape)
    return out[()] if shape == () else out


class _ProgressReporter:
    """progress=None/False: nothing; a callable: called (done, total) from the calling thread;
    True: a tqdm bar if tqdm is installed, else the command line's bar on a terminal."""

    def __init__(self, progress: Progress, label: str):
        self.bar = None
        self.callback: Optional[Callable[[int, int], Any]] = None
        if progress is None or progress is False:
            return
        if progress is True:
            try:
                from tqdm.auto import tqdm
            except ImportError:
                self.callback = _core.progress_bar(label)
                return
            self.bar = tqdm(total=0, desc=label)
            self.callback = self._update
        elif callable(progress):
            self.callback = progress
        else:
            raise TypeError(f"progress must be None, True or a callable(done, total); got {type(progress).__name__}")

    def _update(self, done: int, total: int) -> None:
        if self.bar.total != total:
            self.bar.reset(total=total)
        self.bar.n = done
        self.bar.refresh()

    def __enter__(self):
        return self.callback

    def __exit__(self, *exc):
        if self.bar is not None:
            self.bar.close()


# --- models -------------------------------------------------------------------------------------


class Model:
    """A BRDF named by a spec string, the command line's grammar (models/spec.h):
    NAME[:KEY=VALUE[,KEY=VALUE...]] or a partitive mixture "0.7*minnaert:xi=1 + 0.3*specular:alpha=8"
    (K&P's "partitive mixture of BRDFs"; weights are normalized). `models()` lists every name and parameter. A bad spec
    raises ValueError with the one-line message `ganzfeld` prints."""

    def __init__(self, spec: str):
        if not isinstance(spec, str):
            raise TypeError(f"spec must be a str such as 'specular:alpha=8'; got {type(spec).__name__}")
        self._core = _core.Model(spec)

    @property
    def spec(self) -> str:
        """The canonical spec (every parameter, normalized weights): the material's identity."""
        return self._core.spec

    @property
    def traits(self) -> dict:
        """{isotropic, reciprocal, energy_class}: K&P's constraints (1)-(3), section "General
        Properties of BRDFs" (energy_class: conserving, plausible or not_plausible)."""
        return self._core.traits

    def __repr__(self) -> str:
        return f"ganzfeld.Model({self.spec!r})"

    def _law(self, law: str, i: np.ndarray, j: np.ndarray, tol: float, max_evals: int, progress: Progress) -> Estimate:
        i_rows, j_rows, shape = _pairs(i, j)
        with _ProgressReporter(progress, f"{law} of {self.spec}") as report:
            value, error, evaluations, converged = self._core.evaluate(law, i_rows, j_rows, float(tol),
                                                                       int(max_evals), report)
        return Estimate(*(_shaped(a, shape) for a in (value, error, evaluations, converged)))

    def f(self, i: ArrayLike = None, j: ArrayLike = None, *, theta_i: ArrayLike = None, theta_j: ArrayLike = None,
          phi: ArrayLike = None, cos_theta_i: ArrayLike = None, cos_theta_j: ArrayLike = None):
        """The BRDF f(i, j) in 1/sr, K&P's "Law of Shading" (section "Collimated beam"): exact, no
        error. i and j of shape (..., 3), or theta_i/theta_j (degrees from n; i at azimuth 0) with
        phi (degrees, azimuth of j minus that of i), or cos_theta_i/cos_theta_j; both above the
        surface. Returns an array of the broadcast shape."""
        i = _incident("f", i, theta_i, cos_theta_i)
        j = _outgoing("f", j, theta_j, cos_theta_j, phi)
        return self._law("f", i, j, DEFAULT_TOL, DEFAULT_MAX_EVALS, None).value

    def g(self, i: ArrayLike = None, j: ArrayLike = None, *, theta_i: ArrayLike = None, theta_j: ArrayLike = None,
          phi: ArrayLike = None, cos_theta_i: ArrayLike = None, cos_theta_j: ArrayLike = None,
          tol: float = DEFAULT_TOL, max_evals: int = DEFAULT_MAX_EVALS, progress: Progress = None) -> Estimate:
        """The law of vignetting g(i, j) = ∫_{k·n>0, k·i>0} (k·n) f(k, j) dk: the radiance scattered
        towards j under a uniform sky of unit radiance with pole i, i·n in [-1, 1] (K&P, section
        "Hemispherical diffuse beam"; for white Lambert g = (1 + i·n)/2).

        i (the sky's pole) and j of shape (..., 3), or theta_i in [0, 180] / theta_j in [0, 90]
        degrees with phi (degrees), or cos_theta_i in [-1, 1] / cos_theta_j in [0, 1]; broadcast
        like numpy. tol: absolute tolerance per value; max_evals: evaluation budget per value;
        progress: None, True (tqdm) or a callable(done, total). Returns an Estimate."""
        i = _incident("g", i, theta_i, cos_theta_i)
        j = _outgoing("g", j, theta_j, cos_theta_j, phi)
        return self._law("g", i, j, tol, max_evals, progress)

    def h(self, j: ArrayLike = None, *, theta_j: ArrayLike = None, cos_theta_j: ArrayLike = None,
          phi: ArrayLike = None, tol: float = DEFAULT_TOL, max_evals: int = DEFAULT_MAX_EVALS,
          progress: Progress = None) -> Estimate:
        """The law of darkening h(j) = ∫_{k·n>0} (k·n) f(k, j) dk: the radiance scattered towards j
        in a Ganzfeld of unit radiance (K&P, section "Fully diffuse beam: Ganzfeld"; white
        Lambert: h = 1). j of shape (..., 3), theta_j in [0, 90] degrees or cos_theta_j in [0, 1]
        (phi= matters only for anisotropic models). Returns an Estimate."""
        j = _outgoing("h", j, theta_j, cos_theta_j, phi)
        return self._law("h", np.array([0.0, 0.0, 1.0]), j, tol, max_evals, progress)

    def a(self, i: ArrayLike = None, *, theta_i: ArrayLike = None, cos_theta_i: ArrayLike = None,
          tol: float = DEFAULT_TOL, max_evals: int = DEFAULT_MAX_EVALS, progress: Progress = None) -> Estimate:
        """The albedo a(i) = ∫_{j·n>0} (j·n) f(i, j) dj for a collimated beam from i (K&P, section
        "Fully diffuse beam: Ganzfeld"; a <= 1 is their constraint (3); a = h for reciprocal
        models). i of shape (..., 3), theta_i in [0, 90] degrees or cos_theta_i in [0, 1].
        Returns an Estimate."""
        i = _incident("a", i, theta_i, cos_theta_i)
        return self._law("a", i, np.array([0.0, 0.0, 1.0]), tol, max_evals, progress)

    def r(self, *, tol: float = DEFAULT_TOL, max_evals: int = DEFAULT_MAX_EVALS) -> Estimate:
        """The double-diffuse reflectance r = (1/π) ∫ (i·n) a(i) di, the fraction of a Ganzfeld
        scattered (K&P, section "Fully diffuse beam: Ganzfeld"; white Lambert: r = 1). Returns an
        Estimate of scalars."""
        up = np.array([0.0, 0.0, 1.0])
        return self._law("r", up, up, tol, max_evals, None)


# --- tables -------------------------------------------------------------------------------------


class Table:
    """A baked table of law g, h or a: the same OpenEXR files and lookup as `ganzfeld bake`,
    `info` and `sample` (docs/lut-format.md). `values` and `errors` are read-only float32 arrays
    shaped by the axes (slowest first); `lookup_error` bounds |lookup - law| everywhere (validated
    after baking); `info` is the document of `ganzfeld info --json`."""

    def __init__(self, core: Any):
        self._core = core

    values = property(lambda self: self._core.values, doc="The stored values, shaped by the axes.")
    errors = property(lambda self: self._core.errors, doc="Per-node error bounds (cubature + storage rounding).")
    law = property(lambda self: self._core.law, doc="'g', 'h' or 'a'.")
    model = property(lambda self: self._core.model, doc="The canonical spec of the model baked.")
    lookup_error = property(lambda self: self._core.lookup_error,
                            doc="The table's error: a bound of |lookup - law| anywhere, validated after baking.")
    node_error = property(lambda self: self._core.node_error, doc="The largest per-node error.")
    path = property(lambda self: self._core.path or None, doc="The file read or last written; None in memory.")
    info = property(lambda self: self._core.info, doc="The document of `ganzfeld info --json`.")
    axes = property(lambda self: self.info["axes"], doc="[{name, min, max, count, mapping, [width]}], slowest first.")
    frame = property(lambda self: self.info["frame"], doc="'cosines' or 'lobe' (docs/lut-format.md, \"Axes\").")
    interpolation = property(lambda self: self.info["interpolation"], doc="'linear', 'catmull-rom' or 'b-spline'.")
    encoding = property(lambda self: self.info["encoding"], doc="'float', 'half' or 'unorm16'.")

    def __repr__(self) -> str:
        counts = "x".join(str(a["count"]) for a in self.axes)
        return f"<ganzfeld.Table {self.law} of {self.model!r}, {counts} nodes, lookup error {self.lookup_error:.3g}>"

    def sample(self, *directions: ArrayLike, i: ArrayLike = None, j: ArrayLike = None, theta_i: ArrayLike = None,
               theta_j: ArrayLike = None, phi: ArrayLike = None, cos_theta_i: ArrayLike = None,
               cos_theta_j: ArrayLike = None) -> Lookup:
        """The table's lookup (tables/sample.h), as `ganzfeld sample --json`, at the directions its
        law takes, positionally as the laws take them: sample(i, j) for g, sample(j) for h,
        sample(i) for a; or by keyword, with the angles and cosines of Model.g. Returns a Lookup."""
        law = self.law
        names = {"g": ("i", "j"), "h": ("j",), "a": ("i",)}[law]
        if len(directions) > len(names):
            raise TypeError(f"a table of law {law} takes the directions ({', '.join(names)}); got {len(directions)}")
        given = dict(zip(names, directions))
        if ("i" in given and i is not None) or ("j" in given and j is not None):
            raise TypeError("a direction given both by position and by keyword")
        i, j = given.get("i", i), given.get("j", j)
        up = np.array([0.0, 0.0, 1.0])
        i = _incident(law, i, theta_i, cos_theta_i) if "i" in names else up
        j = _outgoing(law, j, theta_j, cos_theta_j, phi) if "j" in names else up
        i_rows, j_rows, shape = _pairs(i, j)
        value, node_error = self._core.sample(i_rows, j_rows)
        error = np.full(value.shape, self.lookup_error)
        return Lookup(*(_shaped(a, shape) for a in (value, error, node_error)))

    def write(self, path: Union[str, os.PathLike]) -> None:
        """Writes the table as OpenEXR (atomically: a complete file or none), as `ganzfeld bake -o`."""
        self._core.write(os.fspath(path))


def _resolution_text(res: Any) -> str:
    if isinstance(res, str):
        return res
    if isinstance(res, (int, np.integer)):
        return str(int(res))
    try:
        return "x".join(str(int(n)) for n in res)
    except TypeError:
        raise TypeError(f"res must be an int, a tuple of ints or a text such as '32x32x16'; got {res!r}") from None


def bake(model: Union[Model, str], law: str, *, res: Any = None, max_error: Optional[float] = None,
         max_bytes: Optional[int] = None, tol: float = DEFAULT_TOL, max_evals: int = DEFAULT_MAX_EVALS,
         encoding: str = "float", interpolation: Optional[str] = None, frame: Optional[str] = None,
         mapping: Optional[str] = None, checks: Optional[int] = None, progress: Progress = None) -> Table:
    """Bakes law g, h or a of an isotropic model into a Table, as `ganzfeld bake model` (the
    same options by the same names; the same table for the same options):

    res: node counts (int, tuple or '32x32x16'), or max_error: the lookup error to reach (the baker
    then chooses resolution, frame, interpolation and tolerance; max_bytes caps the value bytes).
    tol: the cubature's tolerance per node; encoding: 'float', 'half' or 'unorm16';
    interpolation: 'linear', 'catmull-rom' or 'b-spline'; frame: 'cosines' or 'lobe' (g); mapping: per-axis
    mappings ('cos', 'linearxsqrtxcos', ...); checks: extra random validation points;
    progress: None, True (tqdm) or a callable(done, total). Parallel on every core, GIL released,
    Ctrl-C cancels."""
    m = model if isinstance(model, Model) else Model(model)
    arguments = _core.BakeArguments()
    arguments.res = None if res is None else _resolution_text(res)
    arguments.max_error = None if max_error is None else float(max_error)
    arguments.max_bytes = None if max_bytes is None else int(max_bytes)
    arguments.tol = float(tol)
    arguments.max_evals = int(max_evals)
    arguments.encoding = encoding
    arguments.interpolation = interpolation
    arguments.frame = frame
    arguments.mapping = mapping
    arguments.checks = None if checks is None else int(checks)
    given = {"res": arguments.res, "max_error": max_error, "max_bytes": max_bytes, "tol": tol,
             "encoding": encoding, "interpolation": interpolation, "frame": frame, "mapping": mapping,
             "checks": checks}
    command = f"python: ganzfeld.bake({m.spec!r}, {law!r}" + "".join(
        f", {k}={v!r}" for k, v in given.items() if v is not None) + ")"
    with _ProgressReporter(progress, f"baking {law} of {m.spec}") as report:
        return Table(_core.bake(m._core, law, arguments, command, report))


def read(path: Union[str, os.PathLike]) -> Table:
    """Reads a table written by `ganzfeld bake` or Table.write (format versions 1 and 2,
    docs/lut-format.md); anything else raises ValueError with the one-line message of
    `ganzfeld info`."""
    return Table(_core.read_table(os.fspath(path)))
