#include "tools/validation_reader.h"

#include "tools/input_fields.h"

namespace nfrc {
namespace {

TransientOptions ReadTransient(const nlohmann::json& spec) {
  InputFields fields(spec, "validation.transient");
  TransientOptions o;
  o.relative_tolerance = fields.OptionalNumber("relative_tolerance", o.relative_tolerance);
  o.absolute_scale_factor = fields.OptionalNumber("absolute_scale_factor", o.absolute_scale_factor);
  o.steady_tolerance = fields.OptionalNumber("steady_tolerance", o.steady_tolerance);
  o.steady_periods = fields.OptionalInt("steady_periods", o.steady_periods);
  o.min_periods = fields.OptionalInt("min_periods", o.min_periods);
  o.max_periods = fields.OptionalInt("max_periods", o.max_periods);
  o.max_seconds = fields.OptionalNumber("max_seconds", o.max_seconds);
  o.samples_per_period = fields.OptionalInt("samples_per_period", o.samples_per_period);
  o.max_period_multiple = fields.OptionalInt("max_period_multiple", o.max_period_multiple);
  o.max_step_fraction = fields.OptionalNumber("max_step_fraction", o.max_step_fraction);
  o.explicit_step_fraction =
      fields.OptionalNumber("explicit_step_fraction", o.explicit_step_fraction);
  const std::string solver = fields.OptionalString("linear_solver", "auto");
  if (solver == "auto") {
    o.linear_solver = TransientOptions::LinearSolver::kAuto;
  } else if (solver == "dense") {
    o.linear_solver = TransientOptions::LinearSolver::kDense;
  } else if (solver == "klu") {
    o.linear_solver = TransientOptions::LinearSolver::kKlu;
  } else {
    fields.Fail("linear_solver", "expected \"auto\", \"dense\" or \"klu\", got \"" + solver + "\"");
  }
  fields.Finish();
  o.Validate();
  return o;
}

ChirpSettings ReadChirp(const nlohmann::json& spec) {
  InputFields fields(spec, "validation.chirp");
  ChirpSettings c;
  c.enabled = true;
  c.omega_start = fields.RequiredNumber("omega_start");
  c.omega_end = fields.RequiredNumber("omega_end");
  if (!(c.omega_start > 0.0)) fields.Fail("omega_start", "must be positive");
  if (!(c.omega_end > 0.0) || c.omega_end == c.omega_start) {
    fields.Fail("omega_end", "must be positive and differ from omega_start");
  }
  c.cycles = fields.OptionalNumber("cycles", c.cycles);
  if (!(c.cycles >= 10.0)) fields.Fail("cycles", "must be at least 10");
  c.samples_per_cycle = fields.OptionalInt("samples_per_cycle", c.samples_per_cycle);
  if (c.samples_per_cycle < 8) fields.Fail("samples_per_cycle", "must be at least 8");
  if (fields.Has("directions")) {
    const nlohmann::json& list = fields.RequiredValue("directions");
    c.up = c.down = false;
    if (!list.is_array() || list.empty()) fields.Fail("directions", "expected [\"up\", \"down\"]");
    for (const auto& d : list) {
      if (d == "up") {
        c.up = true;
      } else if (d == "down") {
        c.down = true;
      } else {
        fields.Fail("directions", "entries must be \"up\" or \"down\"");
      }
    }
  }
  fields.Finish();
  return c;
}

MonodromyOptions ReadMonodromy(const nlohmann::json& spec) {
  InputFields fields(spec, "validation.monodromy");
  MonodromyOptions o;
  o.enabled = fields.OptionalBool("enabled", o.enabled);
  o.relative_step = fields.OptionalNumber("relative_step", o.relative_step);
  if (!(o.relative_step >= 1e-10 && o.relative_step <= 1e-2)) {
    fields.Fail("relative_step", "must be in [1e-10, 1e-2]");
  }
  o.scale = fields.OptionalNumber("scale", o.scale);
  if (!(o.scale >= 0.0)) fields.Fail("scale", "must be >= 0 (0: automatic)");
  fields.Finish();
  o.Validate();
  return o;
}

}  // namespace

ValidationSettings ReadValidationSettings(const nlohmann::json& validation) {
  ValidationSettings s;
  if (validation.is_null()) return s;
  InputFields fields(validation, "validation");
  s.omegas = fields.OptionalNumberList("omega");
  for (double omega : s.omegas) {
    if (!(omega > 0.0)) fields.Fail("omega", "frequencies must be positive");
  }
  const std::string start = fields.OptionalString("start", "hbm");
  if (start == "hbm") {
    s.start = ValidationSettings::Start::kHbm;
  } else if (start == "rest") {
    s.start = ValidationSettings::Start::kRest;
  } else {
    fields.Fail("start", "expected \"hbm\" or \"rest\", got \"" + start + "\"");
  }
  if (fields.Has("transient")) s.transient = ReadTransient(fields.RequiredObject("transient"));
  if (fields.Has("chirp")) s.chirp = ReadChirp(fields.RequiredObject("chirp"));
  if (fields.Has("monodromy")) s.monodromy = ReadMonodromy(fields.RequiredObject("monodromy"));
  fields.Finish();
  return s;
}

}  // namespace nfrc
