// What the pressure solve of isph holds (docs/performance.md, "Memory"): the in-place assembly
// of compressed rows (core/linalg/sparse_matrix.hpp) builds the same matrix as the padded-slot
// assembler without keeping the slots, and Method::memory_breakdown accounts for the matrix and
// the Krylov vectors as their sizes say.
#include <string>
#include <vector>

#include <catch2/catch.hpp>

#include "core/base/memory_bytes.hpp"
#include "core/linalg/sparse_matrix.hpp"
#include "core/run/driver.hpp"
#include "support.hpp"

using namespace mps_lab;
using namespace mps_lab::testing;

namespace {

// Row r of a test matrix: its diagonal, then up to 6 off-diagonal entries (columns and values
// from a fixed formula); rows 8 and 31 drop their last entry (as isph drops a pair whose
// coefficient is exactly 0), so they are shorter than their count.
constexpr int kRows = 50;
int counted_length(int row) { return 1 + row % 7; }
template <typename Writer>
void write_row(int row, Writer& writer) {
  writer.add(row, 4.0 + row);
  const int written = counted_length(row) - (row == 8 || row == 31 ? 1 : 0);
  for (int k = 1; k < written; ++k) writer.add((row + 3 * k) % kRows, -1.0 / (row + k));
  writer.close();
}

std::size_t breakdown_entry(const MemoryBreakdown& breakdown, const std::string& name) {
  for (const auto& [key, bytes] : breakdown)
    if (key == name) return bytes;
  FAIL("no entry " << name << " in the memory breakdown");
  return 0;
}

}  // namespace

TEST_CASE("in-place row assembly gives the padded assembler's matrix bit for bit", "[linalg][pressure]") {
  CsrAssembler padded;
  CsrMatrix expected;
  padded.start(kRows, [](int row) { return counted_length(row); });
#pragma omp parallel for schedule(static)
  for (int row = 0; row < kRows; ++row) {
    auto writer = padded.row(row);
    write_row(row, writer);
  }
  padded.finish(expected, true);

  CsrInPlaceAssembler in_place;
  CsrMatrix matrix;
  for (int repeat = 0; repeat < 2; ++repeat) {  // the second time into the kept storage
    in_place.start(matrix, kRows);
#pragma omp parallel for schedule(static)
    for (int row = 0; row < kRows; ++row) in_place.count(row, counted_length(row));
    in_place.place(matrix);
#pragma omp parallel for schedule(static)
    for (int row = 0; row < kRows; ++row) {
      auto writer = in_place.row(row);
      write_row(row, writer);
    }
    in_place.finish(matrix, true);
    CHECK(matrix.rows == expected.rows);
    CHECK(matrix.diagonal_first);
    CHECK(matrix.row_start == expected.row_start);
    CHECK(matrix.column == expected.column);
    CHECK(matrix.value == expected.value);  // exact: the same doubles copied
  }
  // The two dropped entries: the counts' sum less 2.
  int counted = 0;
  for (int row = 0; row < kRows; ++row) counted += counted_length(row);
  CHECK(matrix.nonzeros() == static_cast<std::size_t>(counted - 2));
  // A row with more entries than its count is an error (at finish: close() runs inside the
  // parallel loop), not an overwrite of the next row.
  in_place.start(matrix, 2);
  in_place.count(0, 1);
  in_place.count(1, 1);
  in_place.place(matrix);
  auto second = in_place.row(1);
  second.add(0, 3.0);
  second.close();
  auto first = in_place.row(0);
  first.add(0, 1.0);
  first.add(1, 2.0);  // past row 0's count
  first.close();
  CHECK(matrix.column[1] == 0);  // row 1's entry, not row 0's second
  CHECK(matrix.value[1] == 3.0);
  CHECK_THROWS_AS(in_place.finish(matrix, true), std::logic_error);
}

TEST_CASE("storage that creeps up from step to step grows by an eighth, not by doubling", "[linalg][profile]") {
  // resize_with_headroom (core/base/memory_bytes.hpp): from 1000 elements to 1500 one at a time,
  // as the unknowns or the matrix's entries of a flow creep up, the capacity stays within 1/8 of
  // the largest size (std::vector's own resize doubles: 2000 on libstdc++ after the first step).
  std::vector<double> values(1000);
  for (std::size_t k = 0; k < values.size(); ++k) values[k] = static_cast<double>(k);
  for (std::size_t size = 1001; size <= 1500; ++size) {
    resize_with_headroom(values, size);
    REQUIRE(values.size() == size);
    CHECK(values.capacity() <= size + size / 8);
  }
  CHECK(values[999] == 999.0);  // kept
  CHECK(values[1499] == 0.0);   // value-initialised
  // The in-place assembler sizes the matrix the same way: one more entry each time.
  CsrInPlaceAssembler assembler;
  CsrMatrix matrix;
  for (int rows = 800; rows <= 1000; ++rows) {
    assembler.start(matrix, rows);
    for (int row = 0; row < rows; ++row) assembler.count(row, 1);
    assembler.place(matrix);
    for (int row = 0; row < rows; ++row) {
      auto writer = assembler.row(row);
      writer.add(row, 1.0);
      writer.close();
    }
    assembler.finish(matrix, true);
    REQUIRE(matrix.nonzeros() == static_cast<std::size_t>(rows));
    CHECK(matrix.column.capacity() <= matrix.nonzeros() + matrix.nonzeros() / 8);
    CHECK(matrix.value.capacity() <= matrix.nonzeros() + matrix.nonzeros() / 8);
  }
}

#ifdef MPS_LAB_WITH_ISPH
TEST_CASE("isph memory breakdown: the matrix and the Krylov vectors as their sizes say - no padded rows",
          "[isph][profile]") {
  // amg as at large sizes (the spec's dam break has fewer fluid particles than "auto"'s 2000).
  const Scene scene = load("dambreak.json", {"methods.isph.preconditioner=amg"});
  Simulation simulation(scene, *registries().methods.find("isph"));
  for (int step = 0; step < 3; ++step) simulation.advance();
  const MemoryBreakdown breakdown = simulation.method().memory_breakdown();
  const std::size_t particles = simulation.particles().size();
  // extra[3] and extra[4]: ppe_fluid_unknowns and ppe_wall_unknowns (isph's series_columns).
  const std::size_t unknowns =
      static_cast<std::size_t>(simulation.last_report().extra[3] + simulation.last_report().extra[4]);
  REQUIRE(unknowns > 0);
  // The matrix: at least 4 bytes per row start and 12 per entry (capacity >= size); every row
  // has its diagonal and, inside the fluid, about 20 neighbours (2.4 l0 support on the lattice).
  const std::size_t matrix = breakdown_entry(breakdown, "ppe.matrix");
  CHECK(matrix >= 4 * (unknowns + 1) + 12 * unknowns);
  // BiCGSTAB keeps 7 vectors of the unknowns and the solution one (8 x 8 bytes per unknown at
  // least; the reductions' partial sums add one double per 1024 rows).
  CHECK(breakdown_entry(breakdown, "ppe.solver.krylov_vectors") >= 64 * unknowns);
  // The in-place assembly keeps 4 bytes per row (the written lengths), never the padded slots
  // (12 bytes per entry, at least 13 per row): at most 4 bytes per particle.
  CHECK(breakdown_entry(breakdown, "ppe.assembly_slots") <= 4 * particles);
  CHECK(breakdown_entry(breakdown, "ppe.solver.amg.level0.vectors") > 0);
  // The neighbour list: 4 bytes per particle's offset and per neighbour.
  CHECK(breakdown_entry(breakdown, "neighbour_list") >= 4 * (particles + 1));
}
#endif

#ifdef MPS_LAB_WITH_MPS
TEST_CASE("mps memory breakdown: the matrix, the CG vectors and the search as their sizes say", "[mps][profile]") {
  // amg as at large sizes (the spec's dam break has fewer fluid particles than "auto"'s 2000).
  const Scene scene = load("dambreak.json", {"methods.mps.preconditioner=amg"});
  Simulation simulation(scene, *registries().methods.find("mps"));
  for (int step = 0; step < 3; ++step) simulation.advance();
  const MemoryBreakdown breakdown = simulation.method().memory_breakdown();
  const std::size_t particles = simulation.particles().size();
  // extra[2]: ppe_unknowns (mps's series_columns).
  const auto unknowns = static_cast<std::size_t>(simulation.last_report().extra[2]);
  REQUIRE(unknowns > 0);
  // The matrix: at least 4 bytes per row start and 12 per entry, the diagonal of every row.
  CHECK(breakdown_entry(breakdown, "ppe.matrix") >= 4 * (unknowns + 1) + 12 * unknowns);
  // Conjugate gradients keeps the residual, the direction, the product and the preconditioned
  // residual (4 x 8 bytes per unknown at least), the solution one more.
  CHECK(breakdown_entry(breakdown, "ppe.solver.krylov_vectors") >= 40 * unknowns);
  CHECK(breakdown_entry(breakdown, "ppe.solver.amg.level0.vectors") > 0);
  // The in-place assembly keeps 4 bytes per row (the written lengths), never the padded slots
  // (12 bytes per entry, at least 13 per row inside the fluid): at most 4 bytes per particle.
  CHECK(breakdown_entry(breakdown, "ppe.assembly_slots") <= 4 * particles);
  // The neighbour list: 4 bytes per particle's offset and per neighbour; the step's
  // accelerations 16 bytes per particle.
  CHECK(breakdown_entry(breakdown, "neighbour_list") >= 4 * (particles + 1));
  CHECK(breakdown_entry(breakdown, "step_arrays") >= 16 * particles);
}
#endif

#ifdef MPS_LAB_WITH_DFSPH
TEST_CASE("dfsph memory breakdown: the kernel cache per neighbour pair and the search", "[dfsph][profile]") {
  const Scene scene = load("dambreak.json");
  Simulation simulation(scene, *registries().methods.find("dfsph"));
  for (int step = 0; step < 3; ++step) simulation.advance();
  const MemoryBreakdown breakdown = simulation.method().memory_breakdown();
  const std::size_t particles = simulation.particles().size();
  const std::size_t fluid = simulation.particles().count(ParticleType::Fluid);
  // W_ij (8 bytes) and grad W_ij (16) per neighbour pair; every fluid particle of the lattice
  // has at least its 2 neighbours at l0 inside the support 2 l0 (a corner of the column).
  // No per-pair copy of m_j grad W_ij (16 bytes more) beside them: the neighbour masses are 8
  // bytes per particle. The list holds 4 bytes per pair its storage ever held (>= the cache's
  // pairs), so the cache is at most 6 x the list's bytes plus 8 per particle (40 B per pair
  // would be 10 x).
  const std::size_t kernel_cache = breakdown_entry(breakdown, "kernel_cache");
  CHECK(kernel_cache >= 24 * 2 * fluid);
  CHECK(kernel_cache <= 6 * breakdown_entry(breakdown, "neighbour_list") + 8 * particles);
  CHECK(breakdown_entry(breakdown, "neighbour_list") >= 4 * (particles + 1));
  // The two stiffness arrays (8 bytes each) and the accelerations (16) per particle.
  CHECK(breakdown_entry(breakdown, "step_arrays") >= 32 * particles);
  CHECK(breakdown_entry(breakdown, "solver_workspace") >= 4 * fluid);
}
#endif
