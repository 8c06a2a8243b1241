#include "lab/validation.hpp"

#include "lab/data_directory.hpp"

#include <cmath>
#include <fstream>
#include <limits>
#include <sstream>

#include "core/base/error.hpp"

namespace mps_lab {

std::vector<std::string> split_csv_line(const std::string& line) {
  std::vector<std::string> cells;
  std::stringstream stream(line);
  std::string cell;
  while (std::getline(stream, cell, ',')) cells.push_back(cell);
  return cells;
}

Curve read_curve_csv(const std::string& path, const std::string& x_column, const std::string& y_column) {
  std::ifstream file(path);
  if (!file) throw_input_error(path, "", "cannot open the data file");
  std::string line;
  std::vector<std::string> header;
  Curve curve;
  int x_index = -1, y_index = -1;
  while (std::getline(file, line)) {
    if (line.empty() || line[0] == '#') continue;
    const std::vector<std::string> cells = split_csv_line(line);
    if (header.empty()) {
      header = cells;
      for (std::size_t k = 0; k < header.size(); ++k) {
        if (header[k] == x_column) x_index = static_cast<int>(k);
        if (header[k] == y_column) y_index = static_cast<int>(k);
      }
      if (x_index < 0 || y_index < 0) throw_input_error(path, x_column + "/" + y_column, "column not in the header");
      continue;
    }
    curve.x.push_back(std::stod(cells.at(static_cast<std::size_t>(x_index))));
    curve.y.push_back(std::stod(cells.at(static_cast<std::size_t>(y_index))));
  }
  return curve;
}

double interpolate(const Curve& curve, double x) {
  const std::size_t n = curve.x.size();
  if (n == 0 || x < curve.x.front() || x > curve.x.back()) return std::numeric_limits<double>::quiet_NaN();
  std::size_t hi = 1;
  while (hi < n && curve.x[hi] < x) ++hi;
  if (hi >= n) return curve.y.back();
  const double x0 = curve.x[hi - 1], x1 = curve.x[hi];
  const double s = x1 > x0 ? (x - x0) / (x1 - x0) : 0.0;
  return curve.y[hi - 1] + s * (curve.y[hi] - curve.y[hi - 1]);
}

CurveError curve_error(const Curve& simulated, const Curve& experiment, double shift) {
  CurveError error;
  error.shift = shift;
  double sum2 = 0.0;
  for (std::size_t k = 0; k < experiment.x.size(); ++k) {
    const double value = interpolate(simulated, experiment.x[k] - shift);
    if (std::isnan(value)) continue;
    const double difference = value - experiment.y[k];
    sum2 += difference * difference;
    error.max = std::max(error.max, std::fabs(difference));
    ++error.points;
  }
  error.rms =
      error.points > 0 ? std::sqrt(sum2 / static_cast<double>(error.points)) : std::numeric_limits<double>::quiet_NaN();
  return error;
}

CurveError best_shift_error(const Curve& simulated, const Curve& experiment, double max_shift, double resolution) {
  CurveError best = curve_error(simulated, experiment, 0.0);
  const auto steps = static_cast<long>(std::lround(max_shift / resolution));
  for (long k = -steps; k <= steps; ++k) {
    const CurveError trial = curve_error(simulated, experiment, static_cast<double>(k) * resolution);
    // Compare only shifts that keep every experimental point inside the simulated range.
    if (trial.points == best.points && trial.rms < best.rms) best = trial;
  }
  return best;
}

Curve front_curve(const std::vector<double>& time, const std::vector<double>& front, double column_width,
                  double column_height, double gravity) {
  Curve curve;
  const double scale = std::sqrt(gravity * column_height) / column_width;  // T = t sqrt(g H) / a
  for (std::size_t k = 0; k < time.size(); ++k) {
    curve.x.push_back(time[k] * scale);
    curve.y.push_back(front[k] / column_width);
  }
  return curve;
}

Curve height_curve(const std::vector<double>& time, const std::vector<double>& height, double column_width,
                   double column_height, double gravity) {
  Curve curve;
  const double scale = std::sqrt(gravity / column_width);  // tau = t sqrt(g / a)
  for (std::size_t k = 0; k < time.size(); ++k) {
    curve.x.push_back(time[k] * scale);
    curve.y.push_back(height[k] / column_height);
  }
  return curve;
}

std::string validation_data_path(const std::string& file_name) {
  return data_directory() + "/analysis/validation/" + file_name;
}

}  // namespace mps_lab
