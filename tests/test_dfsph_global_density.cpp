// DFSPH's density solve with global reach (methods/dfsph/dfsph_global_density.hpp,
// methods.dfsph.density_solver = "amg_cg"): the assembled matrix is the correction's
// density response, exactly; it is symmetric; and its solution meets [BK17]'s density
// constraint without a Jacobi iteration where nothing is clamped.
#include <omp.h>
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <random>

#include "core/run/driver.hpp"
#include "core/search/neighbour_search.hpp"
#include "methods/dfsph/dfsph_global_density.hpp"
#include "methods/dfsph/dfsph_operators.hpp"
#include "methods/dfsph/dfsph_solvers.hpp"
#include "support.hpp"

using namespace mps_lab;
using namespace mps_lab::dfsph;
using namespace mps_lab::testing;

namespace {

constexpr double kL0 = 0.025;     // m
constexpr double kRho0 = 1000.0;  // kg/m^3
const double kMass = kRho0 * kL0 * kL0;
constexpr double kDt = 1e-3;  // s

// A three-layer bed and a fluid block above it, the fluid displaced by up to `jitter` l0 and
// given random velocities (m/s) of up to `speed`: a disordered state with walls.
struct Patch {
  ParticleSet particles;
  NeighbourList neighbours;
  KernelCache cache;
  std::vector<double> boundary_mass, density, alpha, counts;
  SphKernel kernel{SphKernelKind::CubicSpline, 2.0 * kL0};

  Patch(int half, int rows, double jitter, double speed, double compression = 1.0) {
    std::mt19937 random(7);
    std::uniform_real_distribution<double> unit(-1.0, 1.0);
    for (int layer = 1; layer <= 3; ++layer) {
      for (int i = -half - 3; i <= half + 3; ++i) {
        particles.add(Vec2(i * kL0, -(layer - 1) * kL0), Vec2::Zero(), ParticleType::Wall,
                      static_cast<std::uint8_t>(layer));
      }
    }
    for (int j = 1; j <= rows; ++j) {
      for (int i = -half; i <= half; ++i) {
        const Vec2 at =
            Vec2(i * kL0 * compression, j * kL0 * compression) + jitter * kL0 * Vec2(unit(random), unit(random));
        particles.add(at, speed * Vec2(unit(random), unit(random)), ParticleType::Fluid);
      }
    }
    neighbours = find_neighbours(particles.position, particles.type, kernel.support());
    compute_kernel_cache(particles, neighbours, kernel, cache);
    compute_boundary_masses(particles, neighbours, cache, 3, kRho0, BoundaryVolume::Lattice, kL0 * kL0, boundary_mass);
    compute_kernel_cache(particles, neighbours, kernel, kMass, boundary_mass, cache);
    const SphSystem sph = system();
    compute_densities(particles, sph, density);
    compute_dfsph_factors(particles, sph, density, alpha);
    count_active_neighbours(particles, sph, counts);
  }
  SphSystem system() const { return {neighbours, cache, boundary_mass, kMass, kRho0}; }
};

// The correction's density response, matrix-free and written out independently of the
// assembly: dv_i = -dt sum_j (s_i + s_j) c_ij (a boundary neighbour: s = 0, at rest), then
// -(1/dt) sum_j c_ij . (dv_i - dv_j) (kg/(m^3 s^2) per unit s).
std::vector<double> response(const Patch& p, const std::vector<double>& s) {
  const std::size_t n = p.particles.size();
  const auto c = [&](std::uint32_t k) {
    const std::uint32_t j = p.neighbours.indices[k];
    const double m = p.particles.type[j] == ParticleType::Fluid ? kMass : p.boundary_mass[j];
    return Vec2(m * p.cache.gradient[k]);
  };
  std::vector<Vec2> dv(n, Vec2::Zero());
  for (std::size_t i = 0; i < n; ++i) {
    if (p.particles.type[i] != ParticleType::Fluid) continue;
    for (std::uint32_t k = p.neighbours.begin(i); k < p.neighbours.end(i); ++k) {
      dv[i] -= kDt * (s[i] + s[p.neighbours.indices[k]]) * c(k);
    }
  }
  std::vector<double> out(n, 0.0);
  for (std::size_t i = 0; i < n; ++i) {
    if (p.particles.type[i] != ParticleType::Fluid) continue;
    for (std::uint32_t k = p.neighbours.begin(i); k < p.neighbours.end(i); ++k) {
      out[i] -= c(k).dot(dv[i] - dv[p.neighbours.indices[k]]) / kDt;
    }
  }
  return out;
}

double entry(const CsrMatrix& a, int row, int column) {
  for (int k = a.row_start[row]; k < a.row_start[row + 1]; ++k) {
    if (a.column[k] == column) return a.value[k];
  }
  return 0.0;
}

}  // namespace

TEST_CASE("DFSPH global density: the surrogate is a symmetric M-matrix, grounded at the free surface",
          "[dfsph][global_density]") {
  const Patch patch(6, 8, 0.15, 0.2);
  GlobalDensityWorkspace w;
  GlobalDensitySettings settings;
  settings.min_neighbours = 8;  // the full lattice count at 2 l0: the top rows are not unknowns
  const std::size_t rows = assemble_density_system(patch.particles, patch.system(), patch.counts, settings, w);
  REQUIRE(rows > 0);
  REQUIRE(rows < patch.particles.count(ParticleType::Fluid));  // some fluid is held at s = 0
  REQUIRE(w.matrix.diagonal_first);
  double asymmetry = 0.0, scale = 0.0;
  std::size_t grounded = 0;
  for (int r = 0; r < w.matrix.rows; ++r) {
    const int first = w.matrix.row_start[r];
    CHECK(w.matrix.column[first] == r);
    CHECK(w.matrix.value[first] > 0.0);
    double row_sum = 0.0;
    for (int k = first; k < w.matrix.row_start[r + 1]; ++k) {
      if (k > first) CHECK(w.matrix.value[k] <= 0.0);  // an M-matrix: a_ij >= 0
      row_sum += w.matrix.value[k];
      scale = std::max(scale, std::abs(w.matrix.value[k]));
      asymmetry = std::max(asymmetry, std::abs(w.matrix.value[k] - entry(w.matrix, w.matrix.column[k], r)));
    }
    // The row sum is what its Dirichlet (surface) neighbours take: 0 for an interior row
    // (walls are Neumann: they add nothing), > 0 for a row next to the surface.
    if (w.grounded[static_cast<std::size_t>(r)] != 0) {
      ++grounded;
      CHECK(row_sum > 1e-6 * w.matrix.value[first]);
    } else {
      CHECK(std::abs(row_sum) <= 1e-12 * w.matrix.value[first]);
    }
  }
  CHECK(grounded > 0);
  CHECK(w.ungrounded_groups == 0);
  CHECK(asymmetry <= 1e-13 * scale);
}

TEST_CASE("DFSPH global density: the surrogate is the correction's density response for smooth stiffness",
          "[dfsph][global_density]") {
  // On the lattice (no walls in reach of the rows compared), s = k (y - y0)^2: both the
  // surrogate -rho0^2 <lap> s and [BK17]'s two-ring response D G s approximate -2 k rho0^2.
  const Patch patch(10, 20, 0.0, 0.0);
  GlobalDensityWorkspace w;
  GlobalDensitySettings settings;
  settings.min_neighbours = 8;  // the full lattice count: the top rows are the Dirichlet surface
  const std::size_t rows = assemble_density_system(patch.particles, patch.system(), patch.counts, settings, w);
  const double k = 1e-3, y0 = 30 * kL0;  // s in m^5/(kg s^2), y in m
  std::vector<double> s(patch.particles.size(), 0.0), x(rows), y(rows);
  for (std::size_t r = 0; r < rows; ++r) {
    const std::size_t i = static_cast<std::size_t>(w.particle_of[r]);
    const double dy = patch.particles.position[i].y() - y0;
    x[r] = s[i] = k * dy * dy;
  }
  multiply(w.matrix, x.data(), y.data());
  const std::vector<double> exact = response(patch, s);
  const double continuum = -2.0 * k * kRho0 * kRho0;
  double worst_surrogate = 0.0, worst_exact = 0.0;
  std::size_t compared = 0;
  for (std::size_t r = 0; r < rows; ++r) {
    const std::size_t i = static_cast<std::size_t>(w.particle_of[r]);
    const Vec2 at = patch.particles.position[i] / kL0;
    if (std::abs(at.x()) > 5.5 || at.y() < 5.5 || at.y() > 15.5) continue;  // 4 l0 from every edge
    ++compared;
    worst_surrogate = std::max(worst_surrogate, std::abs(y[r] / continuum - 1.0));
    worst_exact = std::max(worst_exact, std::abs(exact[i] / continuum - 1.0));
  }
  INFO("rows compared " << compared << ": surrogate off by " << worst_surrogate << ", two-ring response by "
                        << worst_exact);
  REQUIRE(compared >= 100);
  CHECK(worst_surrogate <= 0.03);
  CHECK(worst_exact <= 0.03);
}

TEST_CASE("DFSPH global density: the right-hand side is the predicted compression, averaged, then clamped at 0",
          "[dfsph][global_density]") {
  const Patch patch(6, 8, 0.15, 0.2);
  GlobalDensityWorkspace w;
  const std::size_t rows = assemble_density_system(patch.particles, patch.system(), patch.counts, {}, w);
  density_right_hand_side(patch.particles, patch.system(), patch.density, kDt, w);
  REQUIRE(w.rhs.size() == rows);
  std::vector<double> rate;
  compute_density_change_rate(patch.particles, patch.system(), rate);
  const auto excess = [&](std::size_t i) { return patch.density[i] + kDt * rate[i] - kRho0; };  // [BK17] eq. (9)
  std::size_t compressed = 0, clamped = 0, sign_changed = 0;
  for (std::size_t r = 0; r < rows; ++r) {
    const std::size_t i = static_cast<std::size_t>(w.particle_of[r]);
    double sum = patch.cache.self_value * excess(i), weight = patch.cache.self_value;  // Shepard weights
    for (std::uint32_t k = patch.neighbours.begin(i); k < patch.neighbours.end(i); ++k) {
      const std::uint32_t j = patch.neighbours.indices[k];
      if (j == i || patch.particles.type[j] != ParticleType::Fluid) continue;
      sum += patch.cache.value[k] * excess(j);
      weight += patch.cache.value[k];
    }
    const double average = sum / weight;
    (average > 0.0 ? compressed : clamped) += 1;
    sign_changed += (average > 0.0) != (excess(i) > 0.0);
    CHECK(w.rhs[r] == Approx(std::max(average, 0.0) / (kDt * kDt)).epsilon(1e-12).margin(1e-6));
  }
  CHECK(compressed > 0);
  CHECK(clamped > 0);
  CHECK(sign_changed > 0);  // the average is not the particle's own excess
}

namespace {

// scenes/hydrostatic.json at l0 = 0.005 m (59 rows, 5841 fluid particles) from rest, with the
// setting of the global solve (docs/methods/dfsph.md, "A density solve with global reach"):
// the extrapolated wall pressure, the lattice mass (the lattice at rest density) and the step
// bound 0.25 s/m x l0 = 1.25e-3 s of the million-particle scene.
Scene tall_still_water(const std::string& solver) {
  return load("hydrostatic.json",
              {"method=dfsph", "particle_spacing=0.005", "methods.dfsph.max_time_step=1.25e-3",
               "methods.dfsph.wall_pressure=\"extrapolated\"", "methods.dfsph.particle_mass=\"lattice\"",
               "methods.dfsph.density_solver=\"" + solver + "\""});
}

// Mean p / (rho g (H - y)) of the fluid particles within l0 of height y (the two rows about a depth
// that falls between rows), 0.1 m from the side walls.
double hydrostatic_ratio(const ParticleSet& p, double surface, double y, double spacing) {
  double sum = 0.0;
  int count = 0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    const Vec2 x = p.position[i];
    if (p.type[i] != ParticleType::Fluid || std::abs(x.y() - y) > spacing || x.x() < 0.1 || x.x() > 0.4) continue;
    sum += p.pressure[i] / (1000.0 * 9.81 * (surface - x.y()));
    ++count;
  }
  return count > 0 ? sum / count : 0.0;
}

}  // namespace

TEST_CASE("DFSPH amg_cg builds a tall column's hydrostatic pressure from rest, at the default tolerance",
          "[dfsph][global_density]") {
  // Measured (2026-11-27, walls of the fluid particle's volume): p / rho g (H - y) at depths
  // 0.25 / 0.15 / 0.05 m, the two rows about each depth
  //   amg_cg:         step 1: 0.745 / 0.740 / 0.715;  step 8: 0.982 / 0.981 / 0.978
  //   relaxed_jacobi: step 1: 0 / 0 / 0 (two iterations reach two kernel radii from the bed);
  //                   step 8 (l0^2 walls, the code before): 1.49 / 1.59 / 1.64, and 56 of its
  //                   first 81 solves stop at the cap.
  // Asserted: amg_cg within 3 % at step 8 (three times the measured deviation: the column is
  // still settling from the one-step estimate); above 0.5 after one step (the reach: most of the
  // column's pressure in one step), where the relaxed Jacobi iteration has none (below 0.05); every amg_cg solve
  // converged in its first cycle (2 Jacobi iterations, [BK17]'s minimum).
  const double spacing = 0.005;
  std::vector<Vec2> positions[2];
  for (const std::string solver : {"amg_cg", "relaxed_jacobi"}) {
    const Scene scene = tall_still_water(solver);
    Simulation simulation(scene, *registries().methods.find("dfsph"));
    const double surface = fluid_top(simulation.particles()) + 0.5 * spacing;  // H, m
    for (int step = 1; step <= 8; ++step) {
      const StepReport& report = simulation.advance();
      if (solver == "amg_cg") {
        CHECK(report.solver_iterations == kDefaultCgSmoothing);  // one cycle: the smoother's iterations
        CHECK(report.solver_residual <= 1e-4);
      }
      for (const double depth : {0.25, 0.15, 0.05}) {
        const double ratio = hydrostatic_ratio(simulation.particles(), surface, surface - depth, spacing);
        INFO(solver << " step " << step << " depth " << depth << ": " << ratio);
        if (step == 1 && solver == "amg_cg") CHECK(ratio > 0.5);
        if (step == 1 && solver == "relaxed_jacobi") CHECK(ratio < 0.05);
        if (step == 8 && solver == "amg_cg") CHECK(ratio == Approx(1.0).margin(0.03));
      }
    }
  }
}

namespace {

// A column at the million-particle scene's spacing and height (scenes/dambreak_large.json:
// l0 = 0.05/142 m, 1419 rows, H = 0.5 m), 39 particles wide between two side walls: 55,341
// fluid particles, the height in particles at which the global solve is tested.
Scene million_particle_column(double kernel_support) {
  return parse(R"({
    "particle_spacing": 0.000352112676056338,
    "domain": { "min": [0.0, 0.0], "max": [0.01408450704225352, 0.6] },
    "walls": { "sides": ["bottom", "left", "right"], "layers": 3 },
    "fluid_blocks": [ { "min": [0.0, 0.0], "max": [0.01408450704225352, 0.5] } ],
    "physics": { "density": 1000.0, "kinematic_viscosity": 1.0e-6, "gravity": [0.0, -9.81] },
    "time": { "time_step": 2.5e-5, "end_time": 0.1 },
    "output": { "directory": "output", "frame_every_steps": 1000000, "series_every_steps": 1000000 },
    "method": "dfsph",
    "methods": { "dfsph": { "min_time_step": 1.0e-6, "max_time_step": 8.8e-5, "density_solver": "amg_cg",
                            "wall_pressure": "extrapolated", "particle_mass": "lattice",
                            "kernel_support": )" +
               std::to_string(kernel_support) + R"( } }
  })");
}

}  // namespace

TEST_CASE("DFSPH amg_cg holds a column 1419 particles high from rest: the lattice walls weigh what the fluid weighs",
          "[dfsph][global_density]") {
  // With particle_mass "lattice" the fluid's mass is rho0 / sum_lattice W = rho0 l0^2 / 1.0009
  // (cubic spline, 2 l0); the lattice walls' volume is the fluid particle's, so a uniform
  // stiffness exerts no force on the wall rows (the surrogate's Neumann wall). With the walls at
  // l0^2 (the code before, 2026-11-27) the boundary outweighs the fluid by 0.09 %, a uniform
  // stiffness pushes the fluid off every wall in proportion to the stiffness, which the global
  // solve makes proportional to the height in particles: this column diverged at step 2
  // (6,600 m/s), and the million-particle dam break at step 160.
  // Measured (kernel_support 2.4, 1 thread): p / rho g (H - y) at depths 0.45 / 0.25 / 0.05 m
  // after step 8: 1.011 at mid-depth and 1.011 at the bed (after step 1 0.73, step 2 1.25: the
  // one-step estimate settles). Asserted: within 3 %, as the 59-row column above.
  const Scene scene = million_particle_column(2.4);
  Simulation simulation(scene, *registries().methods.find("dfsph"));
  const ParticleSet& particles = simulation.particles();
  const SphKernel kernel(SphKernelKind::CubicSpline, 2.4 * scene.particle_spacing);
  const double fluid_volume = 1.0 / lattice_kernel_sum(kernel, scene.particle_spacing);  // m^2
  const auto& boundary_volume = particles.field("boundary_volume");
  std::size_t boundary = 0, other_volume = 0;
  for (std::size_t i = 0; i < particles.size(); ++i) {
    if (particles.type[i] != ParticleType::Wall || boundary_volume[i] <= 0.0) continue;
    ++boundary;
    other_volume += std::abs(boundary_volume[i] / fluid_volume - 1.0) > 1e-12;
  }
  CHECK(boundary > 0);
  CHECK(other_volume == 0);
  const double spacing = scene.particle_spacing;
  const double surface = fluid_top(particles) + 0.5 * spacing;  // H, m
  for (int step = 1; step <= 8; ++step) {
    const StepReport& report = simulation.advance();
    CHECK(report.solver_residual <= 1e-4);
  }
  for (const double depth : {0.45, 0.25, 0.05}) {
    double sum = 0.0;
    int count = 0;
    for (std::size_t i = 0; i < particles.size(); ++i) {
      const Vec2 x = particles.position[i];
      if (particles.type[i] != ParticleType::Fluid || std::abs(x.y() - (surface - depth)) > 0.5 * spacing) continue;
      if (x.x() < 5.0 * spacing || x.x() > 35.0 * spacing) continue;  // 4 particles from the side walls
      sum += particles.pressure[i] / (1000.0 * 9.81 * (surface - x.y()));
      ++count;
    }
    INFO("depth " << depth << ": " << sum / count);
    CHECK(sum / count == Approx(1.0).margin(0.03));
  }
}

TEST_CASE("DFSPH amg_cg: 1 and 2 threads give bit-identical particles", "[dfsph][global_density][determinism]") {
  const Scene scene = tall_still_water("amg_cg");
  const int threads = omp_get_max_threads();
  std::vector<Vec2> result[2];
  for (int run = 0; run < 2; ++run) {
    omp_set_num_threads(run == 0 ? 1 : 2);
    Simulation simulation(scene, *registries().methods.find("dfsph"));
    for (int step = 0; step < 5; ++step) simulation.advance();
    result[run] = simulation.particles().position;
  }
  omp_set_num_threads(threads);
  std::size_t different = 0;
  for (std::size_t i = 0; i < result[0].size(); ++i) different += result[0][i] != result[1][i];
  CHECK(different == 0);
}

TEST_CASE("DFSPH amg_cg: what it needs and its own keys are one-line input errors naming the key",
          "[dfsph][global_density]") {
  const MethodInfo& dfsph = *registries().methods.find("dfsph");
  const auto error = [&](const std::vector<std::string>& overrides) -> std::string {
    try {
      const Scene scene = load("dambreak.json", overrides);
      Simulation simulation(scene, dfsph);
    } catch (const InputError& e) {
      return e.what();
    }
    return "";
  };
  CHECK_THAT(error({"methods.dfsph.density_solver=\"amg_cg\""}),
             Catch::Contains("methods.dfsph.density_solver") && Catch::Contains("wall_pressure extrapolated"));
  CHECK_THAT(error({"methods.dfsph.density_solver=\"amg_cg\"", "methods.dfsph.wall_pressure=\"extrapolated\"",
                    "methods.dfsph.wall_treatments.mirror_particles.enabled=true",
                    "methods.dfsph.wall_treatments.akinci_boundary.enabled=false"}),
             Catch::Contains("methods.dfsph.density_solver") && Catch::Contains("wall particles"));
  for (const char* key :
       {"density_cg_tolerance=0.01", "density_cg_max_iterations=50", "density_cg_cycles=2", "density_cg_smoothing=3"}) {
    const std::string name = std::string(key).substr(0, std::string(key).find('='));
    CHECK_THAT(error({std::string("methods.dfsph.") + key}),
               Catch::Contains("methods.dfsph." + name) && Catch::Contains("applies to density_solver amg_cg only"));
  }
  CHECK(error({"methods.dfsph.density_solver=\"amg_cg\"", "methods.dfsph.wall_pressure=\"extrapolated\""}).empty());
  CHECK_THAT(error({"methods.dfsph.particle_mass=\"volume\""}), Catch::Contains("methods.dfsph.particle_mass"));
}
