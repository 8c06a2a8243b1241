#pragma once
// Algebraic multigrid (AMG) preconditioner for the pressure Poisson matrices of the projection
// methods (MPS, ISPH): smoothed aggregation,
//   P. Vaněk, J. Mandel, M. Brezina, "Algebraic multigrid by smoothed aggregation for second
//   and fourth order elliptic problems", Computing 56 (1996) 179-196,
// applied as one W-cycle (or V-cycle) per call, a fixed symmetric linear operator (a preconditioner for CG
// when the matrix is symmetric positive definite; for BiCGSTAB when it is mildly nonsymmetric).
//
// Setup (per level, all O(rows)):
//   1. strength of connection: j is a strong neighbour of i when
//        |a_ij| >= theta_l sqrt(|a_ii a_jj|),  theta_l = strength_threshold * (1/2)^l
//      (the level-dependent threshold of Vaněk et al. 1996, section 5);
//   2. greedy aggregation in breadth-first order (the three passes of Vaněk et al. 1996, section 5):
//      a root and all its strong neighbours when none is aggregated yet; leftovers join the
//      aggregate of a strong neighbour; the rest form aggregates of their own. A row with no
//      strong neighbour (dominated by its diagonal, e.g. next to many Dirichlet neighbours)
//      belongs to no aggregate: the smoother alone resolves it;
//   3. tentative prolongator P0: the constant vector restricted to each aggregate (the near
//      null space of a Poisson operator);
//   4. prolongator smoothing P = (I - omega D_F^-1 A_F) P0, A_F the filtered matrix (weak
//      entries lumped onto the diagonal, so A_F and A agree on constants), omega = 4/3 / rho,
//      rho >= spectral radius of D_F^-1 A_F from Gershgorin's bound;
//   5. restriction R = P^T and the Galerkin coarse matrix A_c = R A P (two sparse products).
// Levels are added until a level has at most `coarsest_size` rows (or stops coarsening); the
// coarsest is solved exactly with a dense LU factorisation (no pivoting: the coarse matrices
// of an M-matrix are symmetric positive definite; a near-zero pivot, from a singular block,
// zeroes its unknown instead of dividing by it).
//
// Apply: one cycle from a zero initial guess, with `smoother_sweeps` steps of a Chebyshev
// polynomial smoother in D^-1 A (default; Adams, Brezina, Hu, Tuminaro, "Parallel multigrid
// smoothing: polynomial versus Gauss-Seidel", J. Comput. Phys. 188 (2003) 593-610) or of
// damped Jacobi, before and after the coarse correction. The same polynomial before and after
// makes the V-cycle symmetric (in exact arithmetic) for a symmetric matrix, and positive
// definite: the Chebyshev interval's upper end is a Gershgorin bound of the spectrum of D^-1 A.
//
// The default smoother is the degree-1 polynomial: x += D^-1 r / theta, theta the centre of
// [rho / chebyshev_ratio, rho] (damped Jacobi with weight 2 / ((1 + 1/30) rho) < 2 / rho, so the
// V-cycle stays positive definite). On the pressure systems of the dam break it needs as few
// or fewer CG / BiCGSTAB iterations than degree 2 on [rho/30, rho] at half the smoothing work
// (docs/performance.md, "A degree-1 smoother": mps 13 / 18 iterations at 4e3 / 1e6 unknowns
// against 14 / 19, isph 9 / 10 against 9 / 12; set-up + solve 0.67 of degree 2's time at 1e6
// unknowns on 2 threads for both).
//
// The cycle: by default a W-cycle (coarse_cycles 2; Trottenberg et al. 2001, §2.4.2): every
// coarse level from coarse_cycle_min_rows rows on, but the coarsest, is cycled twice per visit,
// the second time on the residual the first left. The coarse levels together hold about a fifth
// of the finest level's nonzeros (operator complexity 1.2 on the particle matrices), so the
// second visits add roughly that much work to a cycle, and they keep the iterations flat in the
// number of levels where the V-cycle's grow with it.
//
// Measured (tests/test_amg.cpp, this 2-core machine, 1 thread, degree 1): CG to 1e-8 takes
// 19 iterations on the 5-point Poisson matrix for n = 32 .. 512 and 10-11 on the MPS-kernel
// lattice matrix for 1e3 .. 2.5e5 unknowns (15-16 with jittered points in shuffled order),
// against Jacobi-CG's 102 .. 753 and 122 .. 1816; the V-cycle: 19-20, 11-18 and 18-26.
// Operator complexity 1.1-1.35. On the dam break's pressure systems from rest (2 threads,
// docs/performance.md, "A W-cycle"): mps 12 / 11 / 11 / 11 CG iterations at 1.2e3 / 3.1e4 /
// 1.2e5 / 1.0e6 unknowns (V-cycle 12 / 14 / 16 / 19), isph 7 / 7 / 7 / 8 BiCGSTAB iterations
// (7 / 8 / 9 / 13); the solve at 1e6 takes 0.66x (mps) and 0.63x (isph) the V-cycle's time.
// Before the W-cycle (docs/data/solver_comparison.md, 1 thread): setup 270-560 ns per unknown
// from 1e6 down to 4e3 unknowns (about 15 products with the matrix at 4e3), one V-cycle about
// 29 ns per unknown at 4e3 (3.2 products).
//
// OpenMP over rows everywhere except the aggregation (sequential, O(rows)) and the coarsest
// solve; every sum is taken in a fixed order, so setup() and apply() give the same bits for
// any number of threads. Storage is kept between setups: after the first few calls on
// matrices of similar size and pattern, setup() and apply() allocate nothing.
#include <vector>

#include "core/linalg/krylov.hpp"
#include "core/linalg/sparse_matrix.hpp"

namespace mps_lab {

enum class AmgSmoother {
  chebyshev,      // Chebyshev polynomial of degree smoother_sweeps in D^-1 A
  damped_jacobi,  // smoother_sweeps steps of x += (4/3 / rho) D^-1 (b - A x)
};

struct AmgOptions {
  // theta of the strength test |a_ij| >= theta sqrt(|a_ii a_jj|) on the finest level, halved
  // on each coarser level. 0.02 keeps the MPS kernel's neighbours at distance l0 and sqrt(2) l0
  // (normalised weights 0.17 and 0.07) and drops those at 2 l0 (0.008), giving 3 x 3
  // aggregates on a lattice.
  double strength_threshold = 0.02;
  // Polynomial degree (Chebyshev) or number of sweeps (damped Jacobi), before and after.
  // Degree 1: measured on the projection methods' pressure systems (above).
  int smoother_sweeps = 1;
  AmgSmoother smoother = AmgSmoother::chebyshev;
  // Chebyshev interval [rho / chebyshev_ratio, rho] of D^-1 A (rho: Gershgorin bound).
  double chebyshev_ratio = 30.0;
  // A level with at most this many rows is solved directly (dense LU: O(size^3) flops).
  int coarsest_size = 64;
  int max_levels = 20;
  // false: plain (unsmoothed) aggregation, P = P0; cheaper setup, more iterations.
  bool smooth_prolongator = true;
  // Coarse correction x += coarse_correction_scaling * P e_c (over-correction, > 1, helps
  // plain aggregation; keep 1 with smoothed aggregation). Does not break symmetry.
  double coarse_correction_scaling = 1.0;
  // gamma, the cycles each coarse level gets per visit of the level above: 1, a V-cycle; 2, a
  // W-cycle (Trottenberg, Oosterlee, Schüller, "Multigrid", 2001, §2.4.2): the second one on
  // the residual of the first, rhs - A_c e_c. Symmetric as the V-cycle (B_2 = 2B - BAB for a
  // symmetric level solve B with rho(BA) < 2), so a preconditioner for CG. The coarsest level is
  // solved exactly and is not repeated.
  // Default 2: on the dam break's pressure systems it keeps the iterations flat from 1e3 to 1e6
  // unknowns where the V-cycle's grow (mps 12 -> 19, 11 with W; docs/performance.md, "A W-cycle").
  int coarse_cycles = 2;
  // A coarse level with fewer rows is cycled once whatever coarse_cycles says: at 1.2e3 unknowns
  // (a second level of ~140 rows) the W-cycle's solve took 1.2-1.3x the V-cycle's (isph 8
  // iterations against 7; mps 12 both), from 5e3 unknowns on it is as fast or faster.
  int coarse_cycle_min_rows = 256;
};

struct AmgLevelInfo {
  int rows = 0;
  std::size_t nonzeros = 0;
  std::size_t prolongator_nonzeros = 0;  // 0 on the coarsest level
};

// Per-thread scratch of the sparse matrix products and the prolongator in setup(): the rows a
// thread other than the first computes (the first writes its rows into the result directly),
// and the position of each column in the row being built.
struct AmgThreadScratch {
  std::vector<int> column, position;
  std::vector<double> value;
};

class CheckpointWriter;
class CheckpointReader;

class AmgPreconditioner final : public Preconditioner {
 public:
  explicit AmgPreconditioner(const AmgOptions& options = AmgOptions{});

  // Builds the hierarchy for `matrix`. Keeps a pointer to it: `matrix` must stay alive and
  // unchanged until the next setup() (the Krylov solver owns it for the solve).
  void setup(const CsrMatrix& matrix) override;
  // Keeps the coarse levels and the finest transfer operators of the last setup() (the base)
  // and makes `matrix` the finest level: its smoother is built from `matrix`, and row r of
  // `matrix` is transferred as row base_row_of_row[r] of the base (-1: a row without one, which
  // only the smoother treats). The V-cycle stays symmetric positive definite for a symmetric
  // positive definite `matrix` (R = P^T, coarse operators of the base SPD, the smoother's bound
  // from `matrix`): a valid preconditioner, whose quality decreases as `matrix` departs from
  // the base (docs/performance.md, "A reused hierarchy"). A single-level hierarchy is set up
  // again instead. Keeps a pointer to `matrix`, as setup(). Takes the contents of
  // base_row_of_row (swapped with its own array of the last refresh: nothing is allocated once
  // the sizes have been seen).
  void refresh(const CsrMatrix& matrix, std::vector<int>& base_row_of_row);
  // Checkpoints: what a refresh() after restore_state needs to give the bits of a refresh()
  // without the interruption (the base's transfer operators, coarse levels and coarsest
  // factors; the finest smoother is rebuilt by refresh() from its matrix). restore_state is
  // followed by setup() or refresh(), never by apply().
  void save_state(CheckpointWriter& out) const;
  void restore_state(CheckpointReader& in);
  // result = M^-1 residual (one V-cycle from zero), for residual and result of matrix.rows
  // entries (distinct arrays); apply_in_team by every thread of the caller's region together.
  void apply(const double* residual, double* result) const override;
  void apply_in_team(const double* residual, double* result) const override;

  // The hierarchy of the last setup(), finest first (for reports and tests).
  std::vector<AmgLevelInfo> levels() const;
  // Sum of the nonzeros of every level over those of the finest (dense coarsest: its rows^2).
  double operator_complexity() const;
  // Per level ("level0.matrix", "level0.prolongator", ...) and the shared scratch.
  MemoryBreakdown memory_breakdown() const override;
  const AmgOptions& options() const { return options_; }

  // How a loop of the V-cycle runs: as a worksharing construct of the calling team (a level's
  // rows split among the threads, or one thread of them below a size), or as a plain loop of the
  // one thread that cycles every small level (inside the team's `single`).
  enum class Sharing { team, serial };

 private:
  struct Level {
    CsrMatrix matrix;       // coarse levels only (level 0 uses *fine_matrix_)
    CsrMatrix prolongator;  // rows of this level x rows of the next
    CsrMatrix restriction;  // its transpose
    std::vector<double> inverse_diagonal;
    double spectral_bound = 2.0;  // Gershgorin bound of rho(D^-1 A)
    // V-cycle work vectors (mutable state of the const apply(): one apply at a time).
    mutable std::vector<double> rhs, solution, residual, direction;
    // W-cycle (coarse_cycles 2) of a coarse level: the residual after its first cycle and the
    // second cycle's correction (empty otherwise).
    mutable std::vector<double> second_rhs, second_solution;
  };

  const CsrMatrix& level_matrix(std::size_t level) const;
  void prepare_smoother(std::size_t level, const CsrMatrix& a);
  void size_work_vectors(std::size_t level, std::size_t rows);
  void build_level(std::size_t level);
  void factorise_coarsest();
  void solve_coarsest(const double* rhs, double* solution, Sharing sharing) const;
  void substitute_coarsest(const double* rhs, double* solution) const;
  double chebyshev_inverse_centre(const Level& current) const;
  bool single_step_smoother() const;
  void smooth(std::size_t level, const double* rhs, double* solution, bool zero_initial, Sharing sharing) const;
  void presmooth_with_residual(std::size_t level, const double* rhs, double* solution, double* residual,
                               Sharing sharing) const;
  void postsmooth_from(std::size_t level, const double* rhs, const double* prolonged, double* solution,
                       Sharing sharing) const;
  void cycle(std::size_t level, const double* rhs, double* solution, Sharing sharing) const;
  void repeat_cycle(std::size_t level, Sharing sharing) const;
  void restrict_residual(const Level& current, const double* residual, bool mapped, int fine_rows, double* coarse_rhs,
                         Sharing sharing) const;
  void prolong_correction(const Level& current, const double* coarse, bool mapped, int rows, const double* solution,
                          double* prolonged, Sharing sharing) const;

  AmgOptions options_;
  const CsrMatrix* fine_matrix_ = nullptr;
  std::vector<Level> levels_;  // capacity kept; only the first level_count_ are in use
  std::size_t level_count_ = 0;
  // refresh(): the finest level is not the base's; its rows' base rows and the base rows'
  // current rows (the finest row count for none).
  bool refreshed_ = false;
  int base_rows_ = 0;
  std::vector<int> base_row_of_row_, row_of_base_row_;
  // Dense LU factors of the coarsest matrix (row-major, unit lower + upper).
  std::vector<double> coarsest_factors_;
  mutable std::vector<double> coarsest_work_;
  std::vector<AmgThreadScratch> thread_scratch_;
  // Scratch of build_level(), one for every level (they are built one after the other; the
  // finest sets the size): A P of the Galerkin product, and the aggregation's arrays.
  CsrMatrix product_;             // A P
  std::vector<int> aggregate_;    // per row: aggregate (coarse row), -1 for none
  std::vector<char> strong_;      // per nonzero: strong connection
  std::vector<int> visit_order_;  // breadth-first order of the rows
  std::vector<char> visited_;
};

}  // namespace mps_lab
