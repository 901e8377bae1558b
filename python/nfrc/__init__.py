"""nfrc: nonlinear frequency response curves of structures with friction and contact.

Harmonic balance with pseudo-arclength continuation, over the C++ library. A Case comes from
a case file (load_case) or from a dict with the case-file schema (Case.from_dict, numpy
arrays allowed); its fields can be read and changed, each change validated (InputError names
the field). Analyses: trace (the branch) and solve_at (every solution at one omega). They
run without the GIL; Ctrl-C stops them and raises Interrupted carrying the partial branch.
numpy is needed for matrices and results, not to import the package.
"""

import collections.abc
import contextlib
import json
import os

from . import _nfrc
from ._nfrc import (Bifurcation, Branch, Case, ContactFriction, CoulombFriction, CubicSpring,
                    DlftContact,
                    DlftFriction, EqualityContact,
                    Floquet, Fold, Forcing, HarmonicSet, InputError, Jenkins, LcpContact,
                    PenaltyContact, PolynomialSpring, Solution, Summary, __version__)

__all__ = ["Bifurcation", "Branch", "Case", "ContactFriction", "CoulombFriction", "CubicSpring", "DlftContact",
           "DlftFriction", "EqualityContact",
           "Floquet", "Fold", "Forcing", "HarmonicSet", "InputError", "Interrupted", "Jenkins",
           "LcpContact", "PenaltyContact",
           "PolynomialSpring", "Solution", "Summary", "fold_curve", "load_case", "manifest_members", "neimark_sacker_curve", "peak_curve", "solve_at",
           "sweep", "switch_branch",
           "trace",
           "__version__"]

LAWS = (CubicSpring, PolynomialSpring, CoulombFriction, Jenkins, PenaltyContact, DlftContact,
        LcpContact, EqualityContact, DlftFriction, ContactFriction)

for _cls in LAWS + (Bifurcation, Branch, Case, Floquet, Fold, Forcing, HarmonicSet, InputError,
                    Solution, Summary):
    _cls.__module__ = __name__


class Interrupted(KeyboardInterrupt):
    """Ctrl-C stopped an analysis; `branch` holds the points computed until then."""

    def __init__(self, branch):
        super().__init__(f"interrupted after {branch.points} points")
        self.branch = branch


# Laws and forcing terms are small value classes: fields, repr, equality and copies come
# from their `_fields` (the constructor's keyword arguments).
def _fields(value):
    return {name: getattr(value, name) for name in type(value)._fields}


def _value_repr(self):
    args = ", ".join(f"{name}={v!r}" for name, v in _fields(self).items())
    return f"{type(self).__name__}({args})"


def _value_eq(self, other):
    return type(self) is type(other) and _fields(self) == _fields(other)


def _value_copy(self, memo=None):
    return type(self)(**_fields(self))


for _cls in LAWS + (Forcing,):
    _cls.__repr__ = _value_repr
    _cls.__eq__ = _value_eq
    _cls.__hash__ = None
    _cls.__copy__ = _value_copy
    _cls.__deepcopy__ = _value_copy
    _cls.copy = _value_copy


class _CaseList(collections.abc.MutableSequence):
    """A case's laws or forcing terms. Items are copies: change one and assign it back
    (case.laws[0] = law); every assignment validates the case."""

    def __init__(self, case, attribute):
        self._case = case
        self._attribute = attribute

    def _items(self):
        return getattr(self._case, self._attribute)

    def _assign(self, items):
        setattr(self._case, self._attribute, items)

    def __len__(self):
        return len(self._items())

    def __getitem__(self, index):
        return self._items()[index]

    def __setitem__(self, index, value):
        items = self._items()
        items[index] = value
        self._assign(items)

    def __delitem__(self, index):
        items = self._items()
        del items[index]
        self._assign(items)

    def insert(self, index, value):
        items = self._items()
        items.insert(index, value)
        self._assign(items)

    def __eq__(self, other):
        return list(self) == list(other)

    def __repr__(self):
        return repr(self._items())


class _Options:
    """One options object of a case (a case-file object such as "continuation") under its
    case-file names. Setting one validates the case; update() sets several at once."""

    __slots__ = ("_case",)
    _what = ""  # the case-file object: the case's _<what>() and _set_<what>(dict)

    def __init__(self, case):
        object.__setattr__(self, "_case", case)

    def _get(self):
        return getattr(self._case, "_" + self._what)()

    def _set(self, options):
        getattr(self._case, "_set_" + self._what)(options)

    def __getattr__(self, name):
        options = self._get()
        if name not in options:
            raise AttributeError(f"no {self._what} option {name!r} (known: {', '.join(options)})")
        return options[name]

    def __setattr__(self, name, value):
        self._set({name: value})

    def update(self, **options):
        self._set(options)

    def to_dict(self):
        return self._get()

    def __getitem__(self, name):
        return self._get()[name]

    def __eq__(self, other):
        return self._get() == (other.to_dict() if isinstance(other, _Options) else other)

    def __dir__(self):
        return list(self._get()) + ["update", "to_dict"]

    def __repr__(self):
        return f"{self._what.capitalize()}({self._get()})"


class _Continuation(_Options):
    """A case's continuation options (omega_start, omega_end, step, min_step, max_step,
    max_points, ...)."""

    __slots__ = ()
    _what = "continuation"


class _Stability(_Options):
    """A case's stability options (enabled, unstable_tolerance, bifurcation_tolerance,
    max_bifurcation_iterations, jump_tolerance, hill_modes)."""

    __slots__ = ()
    _what = "stability"


def _plain(value):
    """numpy arrays and scalars to lists and numbers (recursively), for json."""
    if isinstance(value, dict):
        return {str(key): _plain(item) for key, item in value.items()}
    if isinstance(value, (list, tuple)):
        return [_plain(item) for item in value]
    if hasattr(value, "tolist"):  # numpy arrays and scalars, without importing numpy
        return _plain(value.tolist())
    if isinstance(value, os.PathLike):
        return os.fspath(value)
    return value


def _from_dict(cls, source, base_dir=None):
    """A case from a dict with the case-file schema; Matrix Market paths are relative to
    base_dir (default: the current directory)."""
    try:
        text = json.dumps(_plain(source), allow_nan=False)
    except ValueError as error:
        raise InputError(f"case: {error} (NaN and infinity are not valid)") from None
    except TypeError as error:
        raise InputError(f"case: {error}") from None
    return cls._from_json(text, os.fspath(base_dir) if base_dir is not None else os.getcwd())


@contextlib.contextmanager
def _edit(self):
    """Batches changes: the case is validated once when the block ends (so a model can
    change size with its laws); on any error it is left as before the block."""
    self._begin_edit()
    try:
        yield self
    except BaseException:
        self._end_edit(False)
        raise
    self._end_edit(True)


Case.from_dict = classmethod(_from_dict)
Case.edit = _edit
Case.laws = property(lambda self: _CaseList(self, "_laws"),
                     lambda self, laws: setattr(self, "_laws", list(laws)),
                     doc="The laws (CubicSpring, CoulombFriction, ...), as copies.")
Case.forcing = property(lambda self: _CaseList(self, "_forcing"),
                        lambda self, terms: setattr(self, "_forcing", list(terms)),
                        doc="The forcing terms (Forcing), as copies.")
Case.continuation = property(_Continuation,
                             lambda self, options: self._set_continuation(dict(options)),
                             doc="The continuation options (case-file names).")
Case.stability = property(_Stability,
                          lambda self, options: self._set_stability(dict(options)),
                          doc="The stability options (case-file names), e.g. "
                              "case.stability.enabled = False.")


def load_case(path):
    """Reads a case file (JSON, see the README), or a member of a manifest named as
    "FILE.json#NAME"."""
    return Case._load(os.fspath(path))


def manifest_members(path):
    """The members of a manifest (a base case and its variants), each as "FILE.json#NAME" for
    load_case, in the manifest's order."""
    return Case._manifest_members(os.fspath(path))


def _threads(threads):
    """`threads` as the analyses take it: a whole number (a bool or a float is refused)."""
    if isinstance(threads, bool) or not isinstance(threads, int):
        raise TypeError(f"threads: must be a whole number, got {threads!r}")
    return threads


def trace(case, progress=False, threads=-1):
    """Traces the branch of `case`; progress=True prints a line per point on stderr. With the
    case's stability on, Hill's analyses run on `threads` threads beside the trace (-1: one per
    further core; 0: on the tracing thread only); the results are the same for any count."""
    branch = _nfrc._trace(case, bool(progress), _threads(threads))
    if branch.interrupted:
        raise Interrupted(branch)
    return branch


def switch_branch(case, bifurcation, progress=False, threads=-1):
    """The branch born at `bifurcation` (a period_doubling or branch_point of trace(case)):
    the period-2 branch of a period doubling (harmonics of omega/2; branch.period_multiple is
    2 and omega is the forcing frequency) or the other branch through a branch point, as
    `nfrc run` writes to period2_<k>/ and branch_point_<k>/. A switch that finds no start
    returns a branch without points whose summary says why. `threads` as for trace."""
    branch = _nfrc._switch_branch(case, bifurcation, bool(progress), _threads(threads))
    if branch.interrupted:
        raise Interrupted(branch)
    return branch


def fold_curve(case, parameter, to, max_step=0.1, progress=False):
    """Follows each fold of the case's branch in (parameter, omega) towards `to`; `parameter`
    is a case-file path such as "model.forcing[0].cos" or "nonlinearities[0].normal_load".
    Returns a dict: "parameter", "from", "to", "branch_folds", "notes" and "curves", each with
    "start_fold", "start_omega", "termination", "message", the lists "parameter", "omega",
    "energy", "max_abs" (per point a dict by output name) in order along the curve, and "turns"
    (where the curve turns back in the parameter; "cusp" when omega turns too). Ctrl-C stops
    it after the current point: the curves so far are returned with "interrupted" True."""
    return _nfrc._fold_curve(case, str(parameter), float(to), float(max_step), bool(progress))


def peak_curve(case, parameter, to, measure="energy", near=None, at=(), max_step=0.1,
               progress=False):
    """Follows each maximum along omega of `measure` ("energy", "h1:OUT" or "max_abs:OUT" with
    OUT an output DOF's name) on the case's branch in `parameter` towards `to`: the resonance
    peaks where friction leaves no fold. `near`: only the peak nearest this omega; `at`:
    parameter values every curve lands on; steps are at most max_step |to - from|. Returns a
    dict: "parameter", "from", "to", "measure", "branch_events", "notes", "interrupted" and
    "curves", each with "start_omega", "termination" ("reached_to", "vanished", ...),
    "message", "solves" and the lists "parameter", "omega", "measure"."""
    return _nfrc._event_curve(case, "peak", str(parameter), float(to), str(measure),
                              float("nan") if near is None else float(near),
                              [float(v) for v in at], float(max_step), bool(progress))


def neimark_sacker_curve(case, parameter, to, measure="energy", near=None, at=(),
                         max_step=0.1, progress=False):
    """Follows each Neimark-Sacker point of the case's branch (the case needs its stability
    analysis) in `parameter` towards `to`: where the largest complex pair of Floquet
    multipliers has |mu| = 1. `measure` is reported at the points; the rest and the returned
    dict as for peak_curve."""
    return _nfrc._event_curve(case, "neimark_sacker", str(parameter), float(to), str(measure),
                              float("nan") if near is None else float(near),
                              [float(v) for v in at], float(max_step), bool(progress))


def sweep(case, parameter, values=None, progress=False):
    """One branch of `case` per value of `parameter` (a case-file path, as for fold_curve), in
    order: a list of dicts with "value", "values" ({parameter: value}), "status" ("complete",
    "failed", "interrupted" or "pending"), "message" and, for a traced run, "branch" (a Branch,
    as trace returns it). A value the case refuses fails that run only; Ctrl-C stops the
    running branch, whose points are kept, and leaves the rest pending. The branches run one
    after the other; analyses release the GIL, so Python threads can run several sweeps at
    once. `nfrc sweep` writes the same runs to disk, with threads, MPI ranks and resume.

    `case` may also be the path of a case file (or "MANIFEST.json#NAME"): then `parameter` may
    name any numeric field of its JSON ("model.C[0][0]", "harmonics.max", ...), set there and
    the case read again, as `nfrc sweep` does.

    A grid of several parameters: sweep(case, {path: values, path2: values2}) or
    sweep(case, [(path, values), (path2, values2)]), without `values`: one run per point of
    the Cartesian product, the last parameter varying fastest (as `nfrc sweep`), each with
    "values" ({path: v, path2: w}) and no "value"."""
    if values is not None:
        axes = [(str(parameter), [float(v) for v in values])]
    else:
        pairs = parameter.items() if isinstance(parameter, dict) else parameter
        axes = [(str(path), [float(v) for v in vals]) for path, vals in pairs]
    if isinstance(case, (str, os.PathLike)):
        runs = _nfrc._sweep_file(os.fspath(case), axes, bool(progress))
    else:
        runs = _nfrc._sweep(case, axes, bool(progress))
    if values is not None:
        for run in runs:
            (run["value"],) = run["values"].values()
    return runs


def solve_at(case, omega, progress=False):
    """Every solution of the case's branch at `omega` (one per crossing, across folds)."""
    solutions, branch = _nfrc._solve_at(case, float(omega), bool(progress))
    if branch.interrupted:
        raise Interrupted(branch)
    return solutions


def validate(case, omegas=(), start="hbm", chirp=False, progress=False):
    """Checks the case's branch against transient integration at each ω of `omegas` (or the
    case's validation.omega): the HBM solutions there (every crossing), a transient from
    each (start="hbm") or from rest (start="rest"), and how each settled. Returns a dict:
    complete, points (omega, solutions, transients with status, matched, stayed and the
    relative differences), chirps (with chirp=True and a chirp in the case)."""
    result, branch = _nfrc._validate(case, [float(w) for w in omegas], str(start), bool(chirp),
                                     bool(progress))
    if branch.interrupted:
        raise Interrupted(branch)
    result["branch"] = branch
    return result
