// Spec §10 item by item: the CSV frame (header, columns, ghosts left out) and the VTK legacy
// frame (version 3.0, UNSTRUCTURED_GRID of VTK_VERTEX cells, pressure a double scalar, type
// an int scalar, velocity a double vector, ghosts left out), from a hand-built set of three
// particles. The values are short decimals that the writer prints exactly (shortest form).
#include <catch2/catch.hpp>

#include "core/io/output.hpp"
#include "test_mps_spec_support.hpp"

using namespace mps_lab;
using namespace mps_lab::spec_testing;

namespace {

FrameData three_particle_frame() {
  ParticleSet particles;
  particles.add(Vec2(0.1, 0.2), Vec2(0.3, -0.4), ParticleType::Fluid);
  particles.add(Vec2(0.0, 0.0), Vec2::Zero(), ParticleType::Wall, 1);
  particles.add(Vec2(5.0, 5.0), Vec2(7.0, 7.0), ParticleType::Ghost);
  particles.pressure = {1234.5, 10.0, 99.0};
  FrameData frame;
  copy_frame(particles, {}, 0.05, 100, "spec", frame);
  return frame;
}

}  // namespace

TEST_CASE("spec 10.1: the CSV frame is x y vx vy pressure type without ghosts", "[mps][spec][output]") {
  const std::string csv = csv_frame(three_particle_frame());
  CHECK(csv ==
        "x,y,vx,vy,pressure,type\n"
        "0.1,0.2,0.3,-0.4,1234.5,0\n"
        "0,0,0,0,10,1\n");
}

TEST_CASE("spec 10.2: the VTK frame is legacy 3.0 of VTK_VERTEX cells with typed point data and no ghosts",
          "[mps][spec][output]") {
  const std::string vtk = vtk_frame(three_particle_frame());
  const auto has = [&](const std::string& text) {
    INFO(text);
    CHECK(vtk.find(text) != std::string::npos);
  };
  CHECK(vtk.rfind("# vtk DataFile Version 3.0\n", 0) == 0);
  has("\nASCII\nDATASET UNSTRUCTURED_GRID\n");
  has("\nPOINTS 2 double\n0.1 0.2 0\n0 0 0\n");
  has("\nCELLS 2 4\n1 0\n1 1\n");
  has("\nCELL_TYPES 2\n1\n1\n");  // VTK_VERTEX = 1
  has("\nPOINT_DATA 2\n");
  has("\nSCALARS pressure double 1\nLOOKUP_TABLE default\n1234.5\n10\n");
  has("\nSCALARS type int 1\nLOOKUP_TABLE default\n0\n1\n");
  has("\nVECTORS velocity double\n0.3 -0.4 0\n0 0 0\n");
  CHECK(vtk.find("99") == std::string::npos);       // the ghost's pressure
  CHECK(vtk.find("\n5 5 0") == std::string::npos);  // the ghost's position
}
