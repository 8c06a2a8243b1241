// The spec's dam break to t = 2 s (scenes/dambreak.json, spec parameters), against
// Martin & Moyce (1952), n^2 = 2, Table 2 (surge front) and Table 6 (residual height).
#include <catch2/catch.hpp>

#include "dambreak_checks.hpp"

using namespace mps_lab;
using namespace mps_lab::testing;

TEST_CASE("MPS dam break to 2 s: no NaN - nothing lost - nothing through the walls - front on Martin & Moyce",
          "[mps][dambreak][validation]") {
  // The spec's position clamp holds fluid at the wall surfaces (0.5 l0) in every frame.
  const DambreakOutcome outcome = run_spec_dambreak("mps", 0.5);
  const RunEvaluation& e = outcome.evaluation;
  CHECK(outcome.result.steps == 4000);
  CHECK(outcome.frames == 41);
  // The column as the particles represent it: a = 9 l0, H = 19 l0 (docs/validation.md).
  CHECK(outcome.result.summary["column"]["width"].get<double>() == Approx(0.225).epsilon(1e-12));
  CHECK(outcome.result.summary["column"]["height"].get<double>() == Approx(0.475).epsilon(1e-12));
  INFO("front RMS " << e.front_rms << " max " << e.front_max << "; best shift " << e.front_shift << " -> RMS "
                    << e.front_rms_shifted << "; height RMS " << e.height_rms);
  // Measured: RMS 0.126, max 0.243 (the spec's MPS runs ahead of the experiment, as most
  // particle codes do: the experiment's gate opens in finite time). Tolerance 0.15: the
  // RMS difference between two independent experiments on this geometry
  // (analysis/validation/README.md); beyond it the method disagrees with experiment by
  // more than experiments disagree with each other.
  CHECK(e.front_rms < 0.15);
  // With the time shift that the experiment's t = 0 uncertainty allows (|shift| <= 0.3;
  // measured shift 0.10, RMS 0.071), the shape must match to the experimental noise floor
  // of ~0.1 in Z.
  CHECK(e.front_rms_shifted < 0.10);
  CHECK(e.front_shift > 0.0);  // the simulation is ahead, never behind
  // Residual height: measured RMS 0.043 in H*; the table's values are given to 0.01 and
  // digitisations of such tables differ by a few hundredths, so 0.08 flags a real change.
  CHECK(e.height_rms < 0.08);
}

TEST_CASE("MPS load setting: the spec dam break to 2 s with every boundary model",
          "[mps][dambreak][validation][loads]") {
  // The load setting (MethodInfo::load_setting; docs/validation.md, "Each method's load setting")
  // with each boundary model mps supports, applied as `mps_lab run --load-setting --set
  // methods.mps.wall_treatments={"MODEL":{}}` applies it (its collision distance 0.9 l0 then still
  // holds). Measured 2026-11-29: every model completes, front RMS 0.124-0.162, shifted 0.049-0.086;
  // with the spec's collision distance 0.5 l0 only the spec walls completed (the others stopped at
  // 0.34-1.15 s). The bounds: check_load_setting_dambreak (tests/dambreak_checks.hpp).
  check_load_setting_dambreak("mps");
}
