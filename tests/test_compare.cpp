// The comparison metrics (lab/validation.hpp, lab/compare.hpp) on series with a known answer.
#include <catch2/catch.hpp>

#include "core/io/output.hpp"
#include "lab/compare.hpp"
#include "lab/validation.hpp"
#include "support.hpp"

using namespace mps_lab;
using namespace mps_lab::testing;

namespace {

const Curve& table2() {
  static const Curve curve =
      read_curve_csv(validation_data_path("martin_moyce_1952_n2_front.csv"), "T_n_t_sqrt_g_over_a", "Z_x_over_a");
  return curve;
}

// A synthetic run folder: series.csv whose front follows Z(T) = z_of_T(T), sampled every
// dT ~ 0.005 and at the experiment's own T points (so interpolating the series at those
// points is exact and the known answers hold to round-off).
template <typename Function>
std::filesystem::path synthetic_run(const std::string& name, Function z_of_T) {
  const auto folder = fresh_directory("synthetic_" + name);
  const double a = 0.225, h = 0.475, g = 9.81;
  const double scale = std::sqrt(g * h) / a;  // T per second
  nlohmann::json run = {{"method", name},
                        {"status", "completed"},
                        {"steps", 1000},
                        {"wall_seconds", 2.0},
                        {"fluid_particle_steps_per_second", 85500.0},
                        {"solver", {{"mean_iterations", 12.5}}},
                        {"particles", {{"ghost_final", 3}}},
                        {"column", {{"width", a}, {"height", h}}},
                        {"shared", {{"gravity", {0.0, -g}}}}};
  write_text(folder / "run.json", run.dump());
  std::vector<double> times;
  for (int k = 0; k <= 1000; ++k) times.push_back(0.5 * k / 1000.0);
  for (double T : table2().x) times.push_back(T / scale);
  std::sort(times.begin(), times.end());
  std::string series = "step,time,front,height,density_error\n";
  for (std::size_t k = 0; k < times.size(); ++k) {
    const double t = times[k];
    const double tau = t * std::sqrt(g / a);
    series += std::to_string(k) + "," + format_double(t) + "," + format_double(a * z_of_T(t * scale)) + "," +
              format_double(h * std::max(0.0, 1.0 - 0.1 * tau)) + "," + format_double(k == 0 ? 0.0 : 0.02) + "\n";
  }
  write_text(folder / "series.csv", series);
  return folder;
}

double experiment_z(double T) {
  // Table 2 extended linearly before its first point to Z(0) = 1.
  const Curve& data = table2();
  if (T <= data.x.front()) return 1.0 + (data.y.front() - 1.0) * T / data.x.front();
  if (T >= data.x.back()) return data.y.back() + (T - data.x.back()) * 1.0;
  return interpolate(data, T);
}

}  // namespace

TEST_CASE("front metric: a constant offset of 0.1 in Z gives RMS = max = 0.1", "[compare]") {
  const auto folder = synthetic_run("offset", [](double T) { return experiment_z(T) + 0.1; });
  const RunEvaluation row = evaluate_run(folder);
  CHECK(row.front_points == 15);
  CHECK(row.front_rms == Approx(0.1).epsilon(1e-9));
  CHECK(row.front_max == Approx(0.1).epsilon(1e-9));
  // Bookkeeping columns come straight from run.json.
  CHECK(row.method == "offset");
  CHECK(row.mean_solver_iterations == 12.5);
  CHECK(row.ghosts == 3);
  CHECK(row.density_error_mean == Approx(0.02).epsilon(1e-12));  // row 0 (the lattice) excluded
}

TEST_CASE("the time-shift search finds a planted shift", "[compare]") {
  // The simulation runs 0.12 ahead: Z_sim(T) = Z_exp(T + 0.12). Comparing Z_sim(T - s) with
  // Z_exp(T) is exact at s = 0.12; the series is sampled every dT = 0.0048, and linear
  // interpolation of the piecewise-linear Z_exp between samples errs by at most
  // dT * (slope jump) / 4 ~ 0.002, so the RMS at the planted shift is below 0.005.
  const auto folder = synthetic_run("shifted", [](double T) { return experiment_z(T + 0.12); });
  const RunEvaluation row = evaluate_run(folder);
  CHECK(row.front_shift == Approx(0.12).margin(0.002));
  CHECK(row.front_rms_shifted < 0.005);
  CHECK(row.front_rms > 0.05);  // unshifted, the planted lead shows
  // And a simulation that is behind gets a negative shift.
  const RunEvaluation behind = evaluate_run(synthetic_run("behind", [](double T) { return experiment_z(T - 0.2); }));
  CHECK(behind.front_shift == Approx(-0.2).margin(0.002));
}

TEST_CASE("summary.csv has one row per method with every column", "[compare]") {
  const std::vector<RunEvaluation> rows = {
      evaluate_run(synthetic_run("a", [](double T) { return experiment_z(T); })),
      evaluate_run(synthetic_run("b", [](double T) { return experiment_z(T) + 0.05; }))};
  const std::string text = summary_csv(rows);
  const auto header = text.substr(0, text.find('\n'));
  CHECK(header.find("method,status,steps,wall_seconds,particle_steps_per_second,mean_solver_iterations,front_rms") ==
        0);
  std::size_t lines = 0;
  for (char c : text) lines += c == '\n';
  CHECK(lines == 3);
  CHECK(rows[0].front_rms == Approx(0.0).margin(1e-9));
  CHECK(rows[1].front_rms == Approx(0.05).epsilon(1e-9));
}
