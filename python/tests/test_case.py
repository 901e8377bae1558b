"""Cases: reading, fields, and changes validated with errors naming the field."""

import copy
import subprocess
import sys

import numpy as np
import pytest

import nfrc
from conftest import friction_dict


def test_import_does_not_need_numpy(subprocess_env):
    code = ("import sys; sys.modules['numpy'] = None; import nfrc; "
            "c = nfrc.load_case(sys.argv[1]); print(c.harmonics.max, c.continuation.omega_end)")
    out = subprocess.run([sys.executable, "-c", code, "cases/duffing.json"], check=True,
                         capture_output=True, text=True, env=subprocess_env,
                         cwd=str(__import__("conftest").SOURCE_DIR))
    assert out.stdout.split() == ["7", "1.6"]


def test_load_case_reads_every_field(source_dir):
    case = nfrc.load_case(source_dir / "cases/friction/frc_n10.json")
    assert case.title.startswith("Two-DOF friction oscillator")
    assert case.path.endswith("frc_n10.json")
    assert case.harmonics == nfrc.HarmonicSet(59, odd_only=True, samples=1024)
    assert case.harmonics.harmonics[:3] == [1, 3, 5]
    assert case.continuation.omega_start == 0.1 and case.continuation.omega_end == 0.8
    assert case.continuation.method == "arclength"
    assert (case.continuation.start_homotopy, case.continuation.start_homotopy_factor,
            case.continuation.start_homotopy_rungs) == (True, 10.0, 8)
    case.continuation.start_homotopy = False
    assert not case.continuation.start_homotopy
    assert case.output_dofs == [0, 1] and case.output_names == ["x1", "x2"]
    assert case.dof_names == ["x1", "x2"] and case.dof_index("x2") == 1
    np.testing.assert_array_equal(case.K, [[2, -1], [-1, 1]])
    np.testing.assert_array_equal(case.C, [[0.04, -0.02], [-0.02, 0.02]])
    assert list(case.forcing) == [nfrc.Forcing(dof=0, cos=20.0)]
    assert list(case.laws) == [nfrc.CoulombFriction(dof=1, mu=0.9, normal_load=10)]
    assert case.laws[0].law == "min_max" and case.laws[0].type == "coulomb_friction"


def test_manifest_members_are_cases(source_dir):
    """The Fig. 7 manifest: one member per normal load of the paper, each the base case
    (frc_n10.json) with its normal load (and mu = 0 for the linear member)."""
    manifest = source_dir / "cases/friction/fig7.json"
    members = nfrc.manifest_members(manifest)
    assert [m.rsplit("#", 1)[1] for m in members] == ["n8", "n9", "n10", "n10_5", "n11", "n12",
                                                      "linear"]
    base = nfrc.load_case(source_dir / "cases/friction/frc_n10.json")
    for member, load in zip(members, [8, 9, 10, 10.5, 11, 12]):
        case = nfrc.load_case(member)
        assert case.path == member
        assert list(case.laws) == [nfrc.CoulombFriction(dof=1, mu=0.9, normal_load=load)]
        np.testing.assert_array_equal(case.K, base.K)
        assert case.harmonics == base.harmonics
    assert nfrc.load_case(members[-1]).laws[0].mu == 0.0
    with pytest.raises(nfrc.InputError, match=r"fig7.json: manifest.variants: no member \"n7\""):
        nfrc.load_case(f"{manifest}#n7")
    with pytest.raises(nfrc.InputError, match="a manifest of 7 cases"):
        nfrc.load_case(manifest)


def test_from_dict_with_numpy_equals_the_case_file(source_dir):
    built = nfrc.Case.from_dict(friction_dict())
    read = nfrc.load_case(source_dir / "cases/friction/frc_n10.json")
    assert repr(built) == repr(read)
    assert built.continuation.to_dict() == read.continuation.to_dict()
    np.testing.assert_array_equal(built.M, read.M)


def test_from_dict_errors_name_the_field():
    d = friction_dict()
    d["harmonics"]["maxx"] = 3
    with pytest.raises(nfrc.InputError, match=r"harmonics\.maxx"):
        nfrc.Case.from_dict(d)
    d = friction_dict()
    d["nonlinearities"][0]["mu"] = -1
    with pytest.raises(ValueError, match=r"nonlinearities\[0\]\.mu"):
        nfrc.Case.from_dict(d)
    d = friction_dict()
    d["model"]["K"] = np.array([[np.nan, 0], [0, 1]])
    with pytest.raises(nfrc.InputError, match="NaN"):
        nfrc.Case.from_dict(d)


def test_matrix_market_paths_resolve_against_base_dir(source_dir):
    d = {"model": {"type": "matrices", "M": "M.mtx", "K": "K.mtx",
                   "forcing": [{"dof": 0, "cos": 1.0}]},
         "harmonics": {"max": 1}, "continuation": {"omega_start": 1.0, "omega_end": 2.0},
         "output": {"dofs": [0]}}
    case = nfrc.Case.from_dict(d, base_dir=source_dir / "cases/two_rods")
    assert case.num_dofs > 2
    rows, cols, values = case.triplets("K")
    assert len(rows) == len(cols) == len(values) > case.num_dofs


def test_changes_are_validated_and_undone(friction_case):
    case = friction_case
    cases = [
        (lambda: setattr(case.continuation, "omega_start", -1.0), r"continuation\.omega_start"),
        (lambda: setattr(case.continuation, "step", 10.0), r"continuation\.step"),
        (lambda: setattr(case.continuation, "max_points", 0), r"continuation\.max_points"),
        (lambda: setattr(case.continuation, "bogus", 1), r"continuation\.bogus"),
        (lambda: setattr(case, "harmonics", nfrc.HarmonicSet(0)), r"harmonics\.max"),
        (lambda: nfrc.HarmonicSet(5, samples=4), r"harmonics\.samples"),
        (lambda: setattr(case, "output_dofs", ["nope"]), r"output\.dofs\[0\]"),
        (lambda: setattr(case, "output_dofs", [0, 7]), r"output\.dofs\[1\]"),
        (lambda: setattr(case, "signals_at", [-1.0]), r"output\.signals_at"),
        (lambda: setattr(case, "M", np.eye(3)), r"model\.M"),
        (lambda: setattr(case, "K", [[-1, 0], [0, 1]]), r"model\.K"),
        (lambda: case.forcing.append(nfrc.Forcing(dof=9, cos=1)), r"model\.forcing\[1\]\.dof"),
        (lambda: case.forcing.append(nfrc.Forcing(dof=0, cos=1, harmonic=2)), "harmonic set"),
        (lambda: nfrc.CoulombFriction(1, 0.5, 10, law="bogus"), r"^law: unknown friction law"),
    ]
    before = repr(case), case.continuation.to_dict(), list(case.forcing), case.output_dofs
    for change, field in cases:
        with pytest.raises(nfrc.InputError, match=field):
            change()
        assert (repr(case), case.continuation.to_dict(), list(case.forcing),
                case.output_dofs) == before


def test_laws_are_read_changed_and_assigned_back(friction_case):
    case = friction_case
    law = case.laws[0]
    law.normal_load = 12.0
    assert case.laws[0].normal_load == 10.0  # a copy until assigned back
    case.laws[0] = law
    assert case.laws[0].normal_load == 12.0
    law.mu = -0.5
    with pytest.raises(nfrc.InputError, match=r"nonlinearities\[0\]\.mu: must be non-negative"):
        case.laws[0] = law
    law = copy.copy(case.laws[0])
    law.dof = 2
    with pytest.raises(nfrc.InputError, match=r"nonlinearities\[0\]\.dof"):
        case.laws = [law]
    law = nfrc.CoulombFriction(1, 0.9, 10, law="tanh")
    with pytest.raises(nfrc.InputError, match=r"nonlinearities\[0\]\.alpha"):
        case.laws[0] = law
    law.alpha = 100.0
    case.laws[0] = law
    assert case.laws[0].law == "tanh" and case.laws[0].normal_load == 10.0
    case.laws.append(nfrc.CubicSpring(dof=0, coefficient=0.1))
    assert [type(l).__name__ for l in case.laws] == ["CoulombFriction", "CubicSpring"]
    del case.laws[1]
    assert len(case.laws) == 1


def test_every_law_class_round_trips():
    laws = [
        nfrc.CubicSpring(0, 0.1, other=1),
        nfrc.PolynomialSpring(0, [(3, 0.1), (5, 0.01)]),
        nfrc.CoulombFriction(1, 0.9, 10.0, law="piecewise_linear", delta=0.5),
        nfrc.PenaltyContact(0, gap=1.0, stiffness=100.0, direction=-1.0,
                            gap_harmonics=[(1, 0.1, 0.0)]),
        nfrc.DlftContact(0, gap=2e-4, obstacle_stiffness=1e9),
        nfrc.LcpContact(0, gap=2e-4, epsilon=1e9, smoothing=1e-9),
        nfrc.Jenkins(1, 0.9, 10.0, stiffness=100.0, other=0),
        nfrc.DlftFriction(1, 0.9, 10.0, epsilon=10.0),
        nfrc.EqualityContact(0, gap=2e-4, obstacle_stiffness=1e10, rho=1e9),
        nfrc.ContactFriction(0, gap=0.0, tangent_dof=1, mu=0.3, obstacle_stiffness=10.0,
                             friction_rho=2.0),
    ]
    for law in laws:
        assert eval(repr(law), vars(nfrc)) == law
        assert copy.deepcopy(law) == law
    assert laws[4].epsilon is None and laws[4].obstacle_stiffness == 1e9
    assert laws[1].terms == [(3, 0.1), (5, 0.01)]
    with pytest.raises(nfrc.InputError, match="epsilon"):
        nfrc.DlftContact(0, gap=1.0, epsilon=-1.0)


def test_edit_batches_changes(friction_case):
    case = friction_case
    with case.edit():
        case.continuation.update(omega_start=0.2)
        case.continuation.omega_end = 0.2  # invalid in between
        case.continuation.omega_end = 0.3
    assert (case.continuation.omega_start, case.continuation.omega_end) == (0.2, 0.3)
    with pytest.raises(nfrc.InputError, match=r"continuation\.omega_end"):
        with case.edit():
            case.continuation.omega_end = 0.2
    assert case.continuation.omega_end == 0.3
    with case.edit():  # grow the model, move the law onto the new DOF
        case.set_model(M=np.eye(3), K=[[2, -1, 0], [-1, 2, -1], [0, -1, 1]],
                       dof_names=["x1", "x2", "x3"])
        law = case.laws[0]
        law.dof = 2
        case.laws = [law]
        case.output_dofs = ["x3"]
    assert case.num_dofs == 3 and case.output_names == ["x3"] and case.laws[0].dof == 2
    np.testing.assert_array_equal(case.C, np.zeros((3, 3)))


def test_copies_are_independent(friction_case):
    other = friction_case.copy()
    other.title = "copy"
    other.continuation.omega_end = 0.5
    assert friction_case.title != "copy" and friction_case.continuation.omega_end == 0.8


def test_new_laws_are_validated_against_the_model_naming_the_field(source_dir):
    case = nfrc.load_case(source_dir / "cases/friction/frc_n10.json")
    case.laws = [nfrc.Jenkins(1, 0.9, 10.0, stiffness=100.0)]
    assert case.laws[0].stiffness == 100.0
    with pytest.raises(nfrc.InputError, match=r"nonlinearities\[0\]\.stiffness"):
        case.laws = [nfrc.Jenkins(1, 0.9, 10.0, stiffness=-1.0)]
    case.laws = [nfrc.DlftFriction(1, 0.9, 10.0)]
    assert case.laws[0].epsilon is None
    with pytest.raises(nfrc.InputError, match=r"^epsilon"):
        nfrc.DlftFriction(1, 0.9, 10.0, epsilon=-1.0)
    with pytest.raises(nfrc.InputError, match=r"^rho"):
        nfrc.EqualityContact(0, gap=2e-4, rho=0.0)
    case.laws = [nfrc.ContactFriction(0, gap=0.0, tangent_dof=1, mu=0.3)]
    assert case.laws[0].rho is None and case.laws[0].friction_rho == 1.0
    with pytest.raises(nfrc.InputError, match=r"nonlinearities\[0\]\.tangent_dof"):
        case.laws = [nfrc.ContactFriction(0, gap=0.0, tangent_dof=0, mu=0.3)]
