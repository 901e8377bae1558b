#!/usr/bin/env python3
"""Catalogue of bad inputs to the nfrc program: each must end with its documented exit code
and one message that names the file and a field (or option) that is really in the input, in
bounded time, without a crash. usage: bad_inputs.py NFRC_BINARY SOURCE_DIR"""

import copy
import json
import os
import shutil
import signal
import subprocess
import sys
import tempfile
import time

NFRC, SRC = sys.argv[1], sys.argv[2]
# Every bad input is refused before any real work: a few seconds is generous even under the
# sanitizers; a hang is a failure.
TIMEOUT_S = 60
EXIT_INPUT, EXIT_USAGE, EXIT_INCOMPLETE, EXIT_IO = 1, 2, 3, 4

WORK = tempfile.mkdtemp(prefix="nfrc_bad_inputs_")


def load(name):
    with open(os.path.join(SRC, "cases", name)) as f:
        return json.load(f)


DUFFING = load("duffing.json")
ROD = load("rod/rigid_nh20.json")
FRICTION = load("friction/frc_n10.json")


def write(name, content):
    path = os.path.join(WORK, name)
    with open(path, "w") as f:
        f.write(content if isinstance(content, str) else json.dumps(content))
    return path


def edited(base, edit):
    case = copy.deepcopy(base)
    edit(case)
    return case


def setitem(path, value):
    """An edit setting case[path[0]][path[1]]... = value."""
    def edit(case):
        node = case
        for key in path[:-1]:
            node = node[key]
        node[path[-1]] = value
    return edit


def delitem(path):
    def edit(case):
        node = case
        for key in path[:-1]:
            node = node[key]
        del node[path[-1]]
    return edit


CASES = []  # (name, argv, expected exit, substrings every one of which the output contains)


def case_error(name, base, edit, *needles, code=EXIT_INPUT):
    """A case file edited to be wrong: `nfrc run` must name the file and the field."""
    path = write(name + ".json", edited(base, edit))
    CASES.append((name, ["run", path, "--out", os.path.join(WORK, "out_" + name)], code,
                  [path] + list(needles)))


def raw_error(name, text, *needles, code=EXIT_INPUT):
    path = write(name + ".json", text)
    CASES.append((name, ["run", path, "--out", os.path.join(WORK, "out_" + name)], code,
                  [path] + list(needles)))


def command(name, argv, code, *needles):
    CASES.append((name, argv, code, list(needles)))


duffing_text = json.dumps(DUFFING)

# --- the JSON document itself ---------------------------------------------------------------
raw_error("deep_nesting", '{"a":' * 100000 + "1" + "}" * 100000, "nested deeper")
raw_error("deep_nesting_5000", "[" * 5000 + "]" * 5000, "nested deeper")
raw_error("duplicate_key", duffing_text.replace('"title"', '"title": "x", "title"', 1),
          "title: duplicate key")
raw_error("duplicate_nested_key",
          duffing_text.replace('"omega_start"', '"omega_start": 1, "omega_start"', 1),
          "continuation.omega_start: duplicate key")
raw_error("number_overflow", duffing_text.replace('"step": 0.01', '"step": 1e400'),
          "continuation.step", "out of range")
raw_error("negative_overflow", duffing_text.replace('"omega_start": 0.5', '"omega_start": -1e400'),
          "continuation.omega_start", "out of range")
raw_error("not_json", "this is not json", "not valid JSON")
raw_error("truncated_json", duffing_text[: len(duffing_text) // 2], "not valid JSON")
raw_error("empty_file", "", "empty file")
raw_error("top_level_array", "[1, 2, 3]", "expected an object")
raw_error("trailing_garbage", duffing_text + " }", "not valid JSON")
command("case_is_directory", ["run", WORK, "--out", os.path.join(WORK, "o")], EXIT_INPUT,
        WORK, "is a directory")
command("case_is_dev_zero", ["run", "/dev/zero", "--out", os.path.join(WORK, "o")], EXIT_INPUT,
        "/dev/zero", "not a regular file")
command("case_missing", ["run", os.path.join(WORK, "none.json"), "--out",
                         os.path.join(WORK, "o")], EXIT_INPUT, "none.json", "cannot open")

# --- fields of the case ---------------------------------------------------------------------
case_error("unknown_top_key", DUFFING, setitem(["colour"], "red"), "colour: unknown key")
case_error("unknown_continuation_key", DUFFING, setitem(["continuation", "stepp"], 0.1),
           "continuation.stepp: unknown key")
case_error("missing_model", DUFFING, delitem(["model"]), "model: missing")
case_error("missing_harmonics", DUFFING, delitem(["harmonics"]), "harmonics: missing")
case_error("harmonics_max_zero", DUFFING, setitem(["harmonics", "max"], 0), "harmonics.max")
case_error("harmonics_max_2e9", DUFFING, setitem(["harmonics", "max"], 2000000000),
           "harmonics.max")
case_error("harmonics_max_1e5", DUFFING, setitem(["harmonics", "max"], 100000), "harmonics.")
case_error("harmonics_max_string", DUFFING, setitem(["harmonics", "max"], "seven"),
           "harmonics.max", "expected an integer")
case_error("harmonics_max_float", DUFFING, setitem(["harmonics", "max"], 7.5), "harmonics.max")
case_error("samples_too_few", DUFFING, setitem(["harmonics", "samples"], 5), "harmonics.samples")
case_error("samples_4e6", DUFFING, setitem(["harmonics", "samples"], 4000000),
           "harmonics.samples", "oversampling")
case_error("odd_only_not_bool", DUFFING, setitem(["harmonics", "odd_only"], "yes"),
           "harmonics.odd_only")
case_error("omega_start_negative", DUFFING, setitem(["continuation", "omega_start"], -1),
           "continuation.omega_start")
case_error("omega_end_equal", DUFFING, setitem(["continuation", "omega_end"], 0.5),
           "continuation.omega_end")
case_error("plot_measure_unknown", DUFFING, setitem(["continuation", "plot_measure"], "peak"),
           "continuation.plot_measure")
case_error("plot_tolerance_negative", DUFFING, setitem(["continuation", "plot_tolerance"], -1e-3),
           "continuation.plot_tolerance")
case_error("step_negative", DUFFING, setitem(["continuation", "step"], -0.1), "continuation.")
case_error("max_points_zero", DUFFING, setitem(["continuation", "max_points"], 0),
           "continuation.max_points")
case_error("start_homotopy_factor_one", DUFFING,
           setitem(["continuation", "start_homotopy_factor"], 1.0),
           "continuation.start_homotopy_factor")
case_error("start_homotopy_rungs_zero", DUFFING,
           setitem(["continuation", "start_homotopy_rungs"], 0),
           "continuation.start_homotopy_rungs")
case_error("start_homotopy_not_bool", DUFFING, setitem(["continuation", "start_homotopy"], 1),
           "continuation.start_homotopy")
case_error("method_unknown", DUFFING, setitem(["continuation", "method"], "shooting"),
           "continuation.method")
case_error("stepping_points_1e9", load("lcp/rigid_stepping_nt41.json"),
           setitem(["continuation", "points"], 1000000000), "continuation.points")
case_error("stepping_points_one", load("lcp/rigid_stepping_nt41.json"),
           setitem(["continuation", "points"], 1), "continuation.points")
case_error("output_missing", DUFFING, delitem(["output"]), "output: missing")
case_error("output_dofs_empty", DUFFING, setitem(["output", "dofs"], []), "output.dofs")
case_error("output_dof_out_of_range", DUFFING, setitem(["output", "dofs"], [3]),
           "output.dofs[0]")
case_error("output_dof_unknown_name", ROD, setitem(["output", "dofs"], ["tip"]),
           "output.dofs[0]", "tip")
case_error("signals_at_negative", DUFFING, setitem(["output", "signals_at"], [-1.0]),
           "output.signals_at")
case_error("signals_at_1e5", DUFFING,
           setitem(["output", "signals_at"], [0.5 + 1e-5 * i for i in range(100000)]),
           "output.signals_at")
case_error("model_type_unknown", DUFFING, setitem(["model", "type"], "plate"), "model.type")
case_error("mass_not_square", DUFFING, setitem(["model", "M"], [[1, 0]]), "model.M")
case_error("mass_negative", DUFFING, setitem(["model", "M"], [[-1]]), "model.M")
case_error("stiffness_size_mismatch", DUFFING, setitem(["model", "K"], [[1, 0], [0, 1]]),
           "model.")
case_error("matrix_entry_string", DUFFING, setitem(["model", "K"], [["one"]]), "model.K")
case_error("forcing_dof_out_of_range", DUFFING, setitem(["model", "forcing"], [{"dof": 5, "cos": 1}]),
           "model.forcing[0].dof")
case_error("forcing_no_amplitude", DUFFING, setitem(["model", "forcing"], [{"dof": 0}]),
           "model.forcing[0]")
case_error("forcing_harmonic_outside_set", DUFFING,
           setitem(["model", "forcing"], [{"dof": 0, "cos": 1, "harmonic": 9}]), "model.forcing")
case_error("forcing_all_zero", DUFFING, setitem(["model", "forcing"], [{"dof": 0, "cos": 0}]),
           "model.forcing")
case_error("dof_names_duplicate", FRICTION, setitem(["model", "dof_names"], ["x1", "x1"]),
           "model.dof_names", "x1")
case_error("dof_names_wrong_length", FRICTION, setitem(["model", "dof_names"], ["x1"]),
           "model.dof_names")
case_error("rod_elements_zero", ROD, setitem(["model", "elements"], 0), "model.elements")
case_error("rod_elements_1e6", ROD, setitem(["model", "elements"], 1000000), "model")
case_error("rod_length_negative", ROD, setitem(["model", "length"], -1), "model.length")
case_error("modal_damping_negative", ROD, setitem(["model", "damping"], {"modal_ratio": -1}),
           "model.damping.modal_ratio")
case_error("modal_damping_too_large", ROD, setitem(["model", "elements"], 1001),
           "model.damping.modal_ratio", "1001")
case_error("reduction_modes_negative", ROD,
           setitem(["model", "reduction"], {"type": "craig_bampton", "modes": -1}),
           "model.reduction.modes")
case_error("reduction_modes_and_band", ROD,
           setitem(["model", "reduction"], {"type": "craig_bampton", "modes": 2,
                                            "max_frequency": 1e5}), "model.reduction.modes")
case_error("reduction_type_unknown", ROD,
           setitem(["model", "reduction"], {"type": "guyan", "modes": 2}), "model.reduction.type")
case_error("reduction_more_modes_than_interior", ROD,
           setitem(["model", "reduction"], {"type": "craig_bampton", "modes": 25}),
           "model.reduction", "modes")
case_error("reduction_band_negative", ROD,
           setitem(["model", "reduction"], {"type": "craig_bampton", "max_frequency": -1}),
           "model.reduction.max_frequency")
case_error("matrix_market_missing", DUFFING, setitem(["model", "K"], "nowhere.mtx"),
           "model.K", "nowhere.mtx")

# --- laws -----------------------------------------------------------------------------------
case_error("law_type_unknown", DUFFING, setitem(["nonlinearities", 0, "type"], "magic_spring"),
           "nonlinearities[0].type", "magic_spring")
case_error("law_type_missing", DUFFING, delitem(["nonlinearities", 0, "type"]),
           "nonlinearities[0].type")
case_error("law_unknown_key", DUFFING, setitem(["nonlinearities", 0, "stiffness"], 1),
           "nonlinearities[0].stiffness: unknown key")
case_error("law_dof_out_of_range", DUFFING, setitem(["nonlinearities", 0, "dof"], 7),
           "nonlinearities[0].dof")
case_error("law_coefficient_string", DUFFING, setitem(["nonlinearities", 0, "coefficient"], "big"),
           "nonlinearities[0].coefficient")
case_error("friction_mu_negative", FRICTION, setitem(["nonlinearities", 0, "mu"], -0.1),
           "nonlinearities[0].mu")
case_error("friction_law_unknown", FRICTION, setitem(["nonlinearities", 0, "law"], "stribeck"),
           "nonlinearities[0].law", "stribeck")
case_error("friction_alpha_for_exact", FRICTION, setitem(["nonlinearities", 0, "alpha"], 1),
           "nonlinearities[0].alpha")
case_error("friction_other_equals_dof", FRICTION, setitem(["nonlinearities", 0, "other"], 1),
           "nonlinearities[0].other")
case_error("contact_gap_not_finite", ROD, setitem(["nonlinearities", 0, "gap"], "wide"),
           "nonlinearities[0].gap")
case_error("contact_direction", ROD, setitem(["nonlinearities", 0, "direction"], 2),
           "nonlinearities[0].direction")
case_error("contact_epsilon_negative", ROD, setitem(["nonlinearities", 0, "epsilon"], -5),
           "nonlinearities[0].epsilon")
case_error("contact_gap_harmonic_outside_set", ROD,
           setitem(["nonlinearities", 0, "gap"],
                   {"constant": 2e-4, "harmonics": [{"harmonic": 50, "cos": 1e-5}]}),
           "nonlinearities[0].gap")
case_error("contact_obstacle_stiffness_zero", ROD,
           setitem(["nonlinearities", 0, "obstacle_stiffness"], 0),
           "nonlinearities[0].obstacle_stiffness")
JENKINS = copy.deepcopy(FRICTION)
JENKINS["nonlinearities"] = [{"type": "jenkins", "dof": 1, "mu": 0.9, "normal_load": 10,
                              "stiffness": 100}]
case_error("jenkins_stiffness_zero", JENKINS, setitem(["nonlinearities", 0, "stiffness"], 0),
           "nonlinearities[0].stiffness")
case_error("jenkins_normal_load_negative", JENKINS,
           setitem(["nonlinearities", 0, "normal_load"], -1), "nonlinearities[0].normal_load")
DLFT_FRICTION = copy.deepcopy(FRICTION)
DLFT_FRICTION["nonlinearities"] = [{"type": "dlft_friction", "dof": 1, "mu": 0.9,
                                    "normal_load": 10}]
case_error("dlft_friction_epsilon_negative", DLFT_FRICTION,
           setitem(["nonlinearities", 0, "epsilon"], -1), "nonlinearities[0].epsilon")
case_error("dlft_friction_law_key", DLFT_FRICTION, setitem(["nonlinearities", 0, "law"], "tanh"),
           "nonlinearities[0].law")
EQUALITY = copy.deepcopy(ROD)
EQUALITY["nonlinearities"] = [{"type": "equality_contact", "dof": "end", "gap": 2e-4}]
case_error("equality_contact_rho_zero", EQUALITY, setitem(["nonlinearities", 0, "rho"], 0),
           "nonlinearities[0].rho")
case_error("equality_contact_epsilon_key", EQUALITY,
           setitem(["nonlinearities", 0, "epsilon"], 1e9), "nonlinearities[0].epsilon")
CONTACT_FRICTION = load("contact_friction/oscillator.json")
case_error("contact_friction_tangent_dof_missing", CONTACT_FRICTION,
           delitem(["nonlinearities", 0, "tangent_dof"]), "nonlinearities[0].tangent_dof")
case_error("contact_friction_tangent_dof_is_normal", CONTACT_FRICTION,
           setitem(["nonlinearities", 0, "tangent_dof"], "normal"),
           "nonlinearities[0].tangent_dof")
case_error("contact_friction_mu_negative", CONTACT_FRICTION,
           setitem(["nonlinearities", 0, "mu"], -0.1), "nonlinearities[0].mu")
case_error("contact_friction_friction_rho_zero", CONTACT_FRICTION,
           setitem(["nonlinearities", 0, "friction_rho"], 0), "nonlinearities[0].friction_rho")
case_error("contact_friction_normal_load_key", CONTACT_FRICTION,
           setitem(["nonlinearities", 0, "normal_load"], 1), "nonlinearities[0].normal_load")
case_error("validation_omega_negative", DUFFING, setitem(["validation"], {"omega": [-1]}),
           "validation.omega")
case_error("validation_unknown_key", DUFFING, setitem(["validation"], {"omegas": [1]}),
           "validation.omegas")
case_error("stability_enabled_string", DUFFING, setitem(["stability"], {"enabled": "yes"}),
           "stability.enabled", "expected true or false")
case_error("stability_unstable_tolerance_negative", DUFFING,
           setitem(["stability"], {"unstable_tolerance": -1e-6}), "stability.unstable_tolerance")
case_error("stability_bifurcation_tolerance_one", DUFFING,
           setitem(["stability"], {"bifurcation_tolerance": 1.0}),
           "stability.bifurcation_tolerance")
case_error("stability_jump_tolerance_negative", DUFFING,
           setitem(["stability"], {"jump_tolerance": -1e-4}), "stability.jump_tolerance")
case_error("stability_hill_modes_below_minus_one", DUFFING,
           setitem(["stability"], {"hill_modes": -2}), "stability.hill_modes")
case_error("stability_hill_modes_more_than_interior", DUFFING,
           setitem(["stability"], {"hill_modes": 3}), "stability.hill_modes")
case_error("stability_iterations_fraction", DUFFING,
           setitem(["stability"], {"max_bifurcation_iterations": 2.5}),
           "stability.max_bifurcation_iterations", "expected an integer")
case_error("stability_iterations_zero", DUFFING,
           setitem(["stability"], {"max_bifurcation_iterations": 0}),
           "stability.max_bifurcation_iterations")
case_error("stability_unknown_key", DUFFING, setitem(["stability"], {"enable": True}),
           "stability.enable: unknown key")
case_error("stability_not_object", DUFFING, setitem(["stability"], True), "stability")
case_error("validation_monodromy_enabled_not_bool", DUFFING,
           setitem(["validation"], {"monodromy": {"enabled": "yes"}}),
           "validation.monodromy.enabled")
case_error("validation_monodromy_step_zero", DUFFING,
           setitem(["validation"], {"monodromy": {"relative_step": 0}}),
           "validation.monodromy.relative_step")
case_error("validation_monodromy_unknown_key", DUFFING,
           setitem(["validation"], {"monodromy": {"step": 1e-6}}),
           "validation.monodromy.step")

# A numerical failure caused by the input is a status with its cause (exit 3, points kept).
overflow = write("coefficient_1e308.json",
                 edited(DUFFING, setitem(["nonlinearities", 0, "coefficient"], 1e308)))
command("coefficient_1e308", ["run", overflow, "--out", os.path.join(WORK, "out_overflow")],
        EXIT_INCOMPLETE, "not finite", "coefficients")

# --- the hardening round: extremes, reductions, ill-posed models -----------------------------
case_error("reduction_no_interior_modes_0", DUFFING,
           setitem(["model", "reduction"], {"type": "craig_bampton", "modes": 0}),
           "model.reduction", "no interior to reduce")
case_error("reduction_no_interior_band", DUFFING,
           setitem(["model", "reduction"], {"type": "craig_bampton", "max_frequency": 10}),
           "model.reduction", "no interior to reduce")
case_error("reduction_check_frequencies_above_size", ROD,
           setitem(["model", "reduction"], {"type": "craig_bampton", "modes": 2,
                                            "check_frequencies": 5}),
           "model.reduction.check_frequencies", "reduced model has 3 DOFs")
# Masses positive on the diagonal, indefinite as matrices (eigenvalues 3 and -1): the reader's
# diagonal check passes them; the model's and the reduction's checks do not.
TWO_MASSES = copy.deepcopy(FRICTION)
TWO_MASSES["model"]["M"] = [[1, 2], [2, 1]]
case_error("mass_indefinite", TWO_MASSES, setitem(["title"], "indefinite mass"), "model.M",
           "negative eigenvalue")
THREE_DOFS = {"model": {"type": "matrices", "M": [[1, 2, 0], [2, 1, 0], [0, 0, 1]],
                        "K": [[2, -1, 0], [-1, 2, -1], [0, -1, 1]],
                        "C": [[0.02, 0, 0], [0, 0.02, 0], [0, 0, 0.02]],
                        "forcing": [{"dof": 2, "cos": 0.1}],
                        "reduction": {"type": "craig_bampton", "modes": 1}},
              "nonlinearities": [{"type": "cubic_spring", "dof": 2, "coefficient": 0.1}],
              "harmonics": {"max": 3}, "continuation": {"omega_start": 0.2, "omega_end": 2},
              "output": {"dofs": [2]}}
case_error("mass_indefinite_interior", THREE_DOFS, setitem(["title"], "indefinite M_ii"),
           "model.reduction", "interior mass M_ii is not positive definite")
case_error("equality_contact_rho_1e300", EQUALITY, setitem(["nonlinearities", 0, "rho"], 1e300),
           "nonlinearities[0].rho", "useful range")
case_error("dlft_friction_epsilon_1e-300", DLFT_FRICTION,
           setitem(["nonlinearities", 0, "epsilon"], 1e-300), "nonlinearities[0].epsilon",
           "useful range")
case_error("jenkins_mu_normal_load_overflow", JENKINS,
           lambda c: c["nonlinearities"][0].update({"mu": 1e300, "normal_load": 1e300}),
           "nonlinearities[0].normal_load", "overflows")
case_error("lemke_omega_end_9e18", load("lcp/rigid_stepping_nt41.json"),
           setitem(["continuation", "omega_end"], 9.2e18), "continuation.omega_end",
           "frequency scale")
case_error("modal_ratio_7e297", ROD, setitem(["model", "damping"], {"modal_ratio": 7.5e297}),
           "model.damping.modal_ratio", "[0, 10]")
case_error("step_zero", DUFFING, setitem(["continuation", "step"], 0), "continuation.step:",
           "got 0")
case_error("signals_at_outside_range", DUFFING, setitem(["output", "signals_at"], [5.0]),
           "output.signals_at", "outside the traced range")
command("lemke_stepping_with_dlft_names_file",
        ["run", os.path.join(SRC, "tests/tools/data/stepping_dlft.json"), "--out",
         os.path.join(WORK, "out_stepping_dlft")], EXIT_INPUT, "stepping_dlft.json",
        "nonlinearities[0]")
command("singular_model_names_file",
        ["run", os.path.join(SRC, "tests/tools/data/singular.json"), "--out",
         os.path.join(WORK, "out_singular")], EXIT_INPUT, "singular.json", "model")

# --- the command line -----------------------------------------------------------------------
duffing = os.path.join(SRC, "cases", "duffing.json")
rod = os.path.join(SRC, "cases", "rod", "rigid_nh20.json")
out = os.path.join(WORK, "cli_out")
command("no_command", [], EXIT_USAGE, "usage")
command("unknown_command", ["frobnicate"], EXIT_USAGE, "frobnicate")
command("out_without_value", ["run", duffing, "--out"], EXIT_USAGE, "--out")
command("unknown_option", ["run", duffing, "--out", out, "--fast"], EXIT_USAGE, "--fast")
command("two_case_files", ["run", duffing, duffing, "--out", out], EXIT_USAGE, "case file")
command("validate_omega_not_number", ["validate", duffing, "--out", out, "--omega", "abc"],
        EXIT_USAGE, "--omega")
command("validate_start_sideways", ["validate", duffing, "--out", out, "--start", "sideways"],
        EXIT_USAGE, "--start")
command("validate_omega_negative", ["validate", duffing, "--out", out, "--omega", "-1"],
        EXIT_USAGE, "--omega")
command("refine_steps_1e20", ["refine", rod, "--out", out, "--omega", "6e4", "--epsilon0", "1e9",
                              "--steps", "1e20"], EXIT_USAGE, "--steps")
command("refine_factor_nan", ["refine", rod, "--out", out, "--omega", "6e4", "--epsilon0", "1e9",
                              "--factor", "nan"], EXIT_USAGE, "--factor")
command("refine_omega_missing", ["refine", rod, "--out", out], EXIT_USAGE, "--omega")
command("fold_curve_no_parameter", ["fold-curve", duffing, "--out", out, "--to", "0.1"],
        EXIT_USAGE, "--parameter")
command("fold_curve_bad_path", ["fold-curve", duffing, "--out", out, "--parameter",
                                "nonlinearities[0].mu", "--to", "0.1"], EXIT_INPUT,
        "nonlinearities[0].mu")
command("fold_curve_to_nan", ["fold-curve", duffing, "--out", out, "--parameter",
                              "model.forcing[0].cos", "--to", "nan"], EXIT_USAGE, "--to")
command("fold_curve_to_from", ["fold-curve", duffing, "--out", out, "--parameter",
                               "model.forcing[0].cos", "--to", "0.18"], EXIT_INPUT, "to")
command("fold_curve_kind_hopf", ["fold-curve", duffing, "--out", out, "--parameter",
                               "model.forcing[0].cos", "--to", "0.1", "--kind", "hopf"],
        EXIT_USAGE, "--kind")
ns_unstable = write("ns_no_stability.json",
                    edited(DUFFING, setitem(["stability"], {"enabled": False})))
command("neimark_sacker_without_stability", ["fold-curve", ns_unstable, "--out", out, "--kind",
                                             "neimark_sacker", "--parameter",
                                             "model.forcing[0].cos", "--to", "0.1"],
        EXIT_INPUT, ns_unstable, "stability.enabled")
command("peak_curve_bad_measure", ["fold-curve", duffing, "--out", out, "--kind", "peak",
                                    "--parameter", "model.forcing[0].cos", "--to", "0.1",
                                    "--measure", "h3:0"], EXIT_USAGE, "--measure")
command("peak_curve_measure_output", ["fold-curve", duffing, "--out", out, "--kind", "peak",
                                      "--parameter", "model.forcing[0].cos", "--to", "0.1",
                                      "--measure", "h1:x9"], EXIT_USAGE, "x9")
command("peak_curve_station_outside", ["fold-curve", duffing, "--out", out, "--kind", "peak",
                                       "--parameter", "model.forcing[0].cos", "--to", "0.1",
                                       "--at", "0.05"], EXIT_USAGE, "--at")
command("peak_curve_near_negative", ["fold-curve", duffing, "--out", out, "--kind", "peak",
                                     "--parameter", "model.forcing[0].cos", "--to", "0.1",
                                     "--near", "-1"], EXIT_USAGE, "--near")
command("fold_curve_measure_without_peak", ["fold-curve", duffing, "--out", out, "--parameter",
                                            "model.forcing[0].cos", "--to", "0.1", "--measure",
                                            "energy"], EXIT_USAGE, "--measure")
command("sweep_no_values", ["sweep", duffing, "--out", out, "--parameter",
                            "model.forcing[0].cos"], EXIT_USAGE, "--values")
command("sweep_range_short", ["sweep", duffing, "--out", out, "--parameter",
                              "model.forcing[0].cos", "--range", "0.1:0.2"], EXIT_USAGE, "--range")
command("sweep_range_count_1", ["sweep", duffing, "--out", out, "--parameter",
                                "model.forcing[0].cos", "--range", "0.1:0.2:1"], EXIT_USAGE,
        "--range")
command("run_threads_negative", ["run", duffing, "--out", out, "--threads", "-2"], EXIT_USAGE,
        "--threads")
command("run_threads_word", ["run", duffing, "--out", out, "--threads", "all"], EXIT_USAGE,
        "--threads")
command("sweep_jobs_0", ["sweep", duffing, "--out", out, "--parameter", "model.forcing[0].cos",
                         "--values", "0.1", "--jobs", "0"], EXIT_USAGE, "--jobs")
command("sweep_bad_path", ["sweep", duffing, "--out", out, "--parameter", "model.mass",
                           "--values", "0.1"], EXIT_INPUT, "model.mass")
FORCE, K3 = "model.forcing[0].cos", "nonlinearities[0].coefficient"
command("sweep_grid_parameter_without_values", ["sweep", duffing, "--out", out, "--parameter",
                                                FORCE, "--values", "0.1", "--parameter", K3],
        EXIT_USAGE, "--parameter " + K3, "--values")
command("sweep_grid_two_lists", ["sweep", duffing, "--out", out, "--parameter", FORCE, "--values",
                                 "0.1", "--range", "0.1:0.2:2", "--parameter", K3, "--values",
                                 "0.1"], EXIT_USAGE, "--parameter " + FORCE, "--range")
command("sweep_grid_same_path", ["sweep", duffing, "--out", out, "--parameter", FORCE, "--values",
                                 "0.1", "--parameter", FORCE, "--values", "0.2"], EXIT_USAGE,
        "--parameter " + FORCE, "more than once")
command("sweep_grid_values_first", ["sweep", duffing, "--out", out, "--values", "0.1",
                                    "--parameter", FORCE, "--parameter", K3, "--values", "0.1"],
        EXIT_USAGE, "--values", "after the --parameter")
command("sweep_grid_too_large", ["sweep", duffing, "--out", out, "--parameter", FORCE, "--range",
                                 "0:1:1000", "--parameter", K3, "--range", "0:1:1000"], EXIT_USAGE,
        "--parameter", "1000000 runs")
command("sweep_grid_bad_second_path", ["sweep", duffing, "--out", out, "--parameter", FORCE,
                                       "--values", "0.1", "--parameter", "model.mass", "--values",
                                       "0.1"], EXIT_INPUT, "model.mass")
command("plot_measure_volume", ["plot", out, "--measure", "volume"], EXIT_USAGE, "--measure")
command("fold_curve_parameter_named_as_option",
        ["fold-curve", duffing, "--out", out, "--parameter", "model.forcing", "--to", "0.1"],
        EXIT_INPUT, "--parameter:", "model.forcing")
command("fold_curve_to_named_as_option",
        ["fold-curve", duffing, "--out", out, "--parameter", FORCE, "--to", "0.18"],
        EXIT_INPUT, "--to:")
command("fold_curve_to_1e308", ["fold-curve", duffing, "--out", out, "--parameter", FORCE,
                                "--to", "1e308"], EXIT_INPUT, "--to:", "in stages")
command("peak_curve_to_1e308", ["fold-curve", duffing, "--out", out, "--kind", "peak",
                                "--parameter", FORCE, "--to", "1e308"], EXIT_INPUT, "--to:",
        "in stages")
command("refine_omega_named_as_option",
        ["refine", rod, "--out", out, "--omega", "1e6", "--epsilon0", "1e9"], EXIT_INPUT,
        "--omega:", "range")

# sweep.json of the wrong types in a directory that holds this very sweep (exit 1, the file and
# the field), and a directory in its place.
SWEEP_DIR = os.path.join(WORK, "sweep_record")
SWEEP_ARGS = ["sweep", os.path.join(SRC, "cases", "duffing_h1.json"), "--parameter", FORCE,
              "--values", "0.05"]
subprocess.run([NFRC] + SWEEP_ARGS + ["--out", SWEEP_DIR], capture_output=True, timeout=TIMEOUT_S)
with open(os.path.join(SWEEP_DIR, "sweep.json")) as f:
    GOOD_RECORD = json.load(f)


def bad_record(name, edit, *needles):
    folder = os.path.join(WORK, "sweep_record_" + name)
    shutil.copytree(SWEEP_DIR, folder)
    record = copy.deepcopy(GOOD_RECORD)
    edit(record)
    with open(os.path.join(folder, "sweep.json"), "w") as f:
        json.dump(record, f)
    command("sweep_record_" + name, SWEEP_ARGS + ["--out", folder], EXIT_INPUT,
            os.path.join(folder, "sweep.json"), *needles)


bad_record("index_string", lambda r: r["runs"][0].update({"index": "zero"}), "runs[0].index")
bad_record("runs_number", lambda r: r.update({"runs": 5}), "runs")
bad_record("peaks_list", lambda r: r["runs"][0].update({"peaks": [1]}), "runs[0].peaks")
bad_record("status_unknown", lambda r: r["runs"][0].update({"status": "done"}), "runs[0].status")
SWEEP_DIR_RECORD_DIR = os.path.join(WORK, "sweep_record_is_directory")
os.makedirs(os.path.join(SWEEP_DIR_RECORD_DIR, "sweep.json"))
command("sweep_record_is_directory", SWEEP_ARGS + ["--out", SWEEP_DIR_RECORD_DIR], EXIT_INPUT,
        "sweep.json", "is a directory")
EDITED = edited(load("duffing_h1.json"), setitem(["nonlinearities", 0, "coefficient"], 5))
command("sweep_resumed_on_another_case",
        ["sweep", write("duffing_k3_5.json", EDITED), "--parameter", FORCE, "--values", "0.05",
         "--out", SWEEP_DIR], EXIT_INPUT, "--out", "of another case")
command("run_into_a_sweep_run_folder",
        ["run", duffing, "--out", os.path.join(SWEEP_DIR, "0")], EXIT_INPUT, "--out",
        "run folder of a sweep")


def run(name, argv, code, needles):
    started = time.monotonic()
    try:
        result = subprocess.run([NFRC] + argv, capture_output=True, text=True, timeout=TIMEOUT_S)
    except subprocess.TimeoutExpired:
        return f"FAIL {name}: no answer within {TIMEOUT_S} s"
    output = result.stdout + result.stderr
    problems = []
    if result.returncode < 0:
        problems.append(f"killed by signal {-result.returncode}")
    if result.returncode != code:
        problems.append(f"exit {result.returncode}, want {code}")
    for needle in needles:
        if needle not in output:
            problems.append(f"message lacks {needle!r}")
    if "internal error" in output or "AddressSanitizer" in output or "runtime error" in output:
        problems.append("sanitizer report or internal error")
    took = time.monotonic() - started
    if problems:
        return f"FAIL {name} ({took:.1f} s): {'; '.join(problems)}\n     output: {output.strip()[:400]}"
    return f"ok   {name} ({took:.1f} s)"


def main():
    assert len(CASES) >= 60, f"the catalogue needs at least 60 bad inputs, has {len(CASES)}"
    failed = 0
    for name, argv, code, needles in CASES:
        line = run(name, argv, code, needles)
        print(line, flush=True)
        failed += line.startswith("FAIL")
    print(f"{len(CASES) - failed} passed, {failed} failed")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
