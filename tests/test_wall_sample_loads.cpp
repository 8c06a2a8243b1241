// Loads on obstacles with the boundary models of wall samples (core/walls/wall_sample_reactions.hpp;
// docs/walls.md "Loads on obstacles"): every sample names the solid it stands for. The methods'
// sample pair terms are tested in tests/test_<method>_loads.cpp.
#include <catch2/catch.hpp>

#include <vector>

#include "still_water_obstacles.hpp"
#include "support.hpp"

using namespace mps_lab;
using namespace mps_lab::testing;

namespace {

bool inside(const Vec2& x, const Vec2& low, const Vec2& high, double eps) {
  return x.x() > low.x() - eps && x.x() < high.x() + eps && x.y() > low.y() - eps && x.y() < high.y() + eps;
}

}  // namespace

TEST_CASE("wall sample loads: every sample names the solid it stands for", "[walls][loads]") {
  // The box's surface [0.1875, 0.3125] x [0.0875, 0.1625] m, the plate's [0.4375, 0.4875] x
  // [0.0125, 0.5125] m (tests/still_water_obstacles.hpp). A sample of obstacle k lies in k's solid;
  // one of the tank (-1) lies in neither obstacle's solid, or below the bed's surface y = 0.0125 m
  // (the bed under the plate's foot is the tank's, as its wall particles are) or beyond the right
  // wall's surface x = 0.4875 m (the plate's back stands against it); every sample below the bed's
  // surface is the tank's.
  const double eps = 1e-9;
  const Vec2 box_low(0.1875, 0.0875), box_high(0.3125, 0.1625);
  const Vec2 plate_low(0.4375, 0.0125), plate_high(0.4875, 0.5125);
  REQUIRE(sample_models().size() >= 3);
  for (const WallTreatmentInfo* model : sample_models()) {
    INFO(model->name);
    const SampleState state = sample_state(*model, 2.4 * 0.025);
    std::size_t counts[3] = {0, 0, 0};  // tank, box, plate
    for (const WallSample& sample : state.samples.samples) {
      const Vec2& x = sample.position;
      INFO("sample at " << x.transpose() << " of obstacle " << sample.obstacle);
      REQUIRE(sample.obstacle >= -1);
      REQUIRE(sample.obstacle <= 1);
      ++counts[sample.obstacle + 1];
      if (sample.obstacle == 0) CHECK(inside(x, box_low, box_high, eps));
      if (sample.obstacle == 1) CHECK(inside(x, plate_low, plate_high, eps));
      if (sample.obstacle == -1) {
        CHECK_FALSE(inside(x, box_low, box_high, -eps));
        const bool in_plate = inside(x, plate_low, plate_high, -eps);
        CHECK((!in_plate || x.y() < 0.0125 || x.x() > 0.4875));
      }
      if (x.y() < 0.0125 - eps) CHECK(sample.obstacle == -1);
    }
    CHECK(counts[0] > 0);
    CHECK(counts[1] > 0);
    CHECK(counts[2] > 0);
  }
}
