#pragma once
// Comparison with experiments: Martin & Moyce (1952), Phil. Trans. R. Soc. A 244, 312-324.
//
// Non-dimensional variables (M&M's own, for a column of width a and height H = n^2 a):
//   surge front      Z = z / a          against  T   = n t sqrt(g/a) = t sqrt(g H) / a
//   residual height  H* = h / H         against  tau = t sqrt(g/a)
// with a and H the column as the particles represent it, measured from the wall surfaces
// (run.json "column": the front and height at t = 0). For the spec's lattice a = 0.225 m,
// H = 0.475 m (n^2 = 2.11); the experiment is n^2 = 2. See docs/validation.md.
#include <string>
#include <vector>

namespace mps_lab {

struct Curve {
  std::vector<double> x;
  std::vector<double> y;
};

// Reads two columns (by header name) of a CSV whose comment lines start with '#'.
Curve read_curve_csv(const std::string& path, const std::string& x_column, const std::string& y_column);

// The cells of one line of a CSV file (comma-separated, no quoting: the files mps_lab writes
// and the experimental data).
std::vector<std::string> split_csv_line(const std::string& line);

// Linear interpolation of a curve with increasing x; NaN outside [x.front(), x.back()].
double interpolate(const Curve& curve, double x);

struct CurveError {
  double rms = 0.0;        // root-mean-square of (simulated - experimental) over the points
  double max = 0.0;        // largest |simulated - experimental|
  double shift = 0.0;      // the simulation is compared at x - shift (positive: simulation ahead)
  std::size_t points = 0;  // experimental points inside the simulated range
};

// Error of `simulated` at the experiment's own x points, simulated evaluated at x - shift.
CurveError curve_error(const Curve& simulated, const Curve& experiment, double shift = 0.0);
// The shift in [-max_shift, max_shift] (searched in steps of `resolution`) with least RMS.
CurveError best_shift_error(const Curve& simulated, const Curve& experiment, double max_shift = 0.3,
                            double resolution = 0.001);

// Non-dimensional front Z(T) and height H*(tau) of a run's series.
Curve front_curve(const std::vector<double>& time, const std::vector<double>& front, double column_width,
                  double column_height, double gravity);
Curve height_curve(const std::vector<double>& time, const std::vector<double>& height, double column_width,
                   double column_height, double gravity);

// The validation data shipped with the project (analysis/validation/).
std::string validation_data_path(const std::string& file_name);

}  // namespace mps_lab
