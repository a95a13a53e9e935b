// Internal: the quadratic model of one fitting iteration: assembly of the sensors' quadratic forms
// and the smoothing energy into a sparse symmetric system over the control points, and its
// solution.
#pragma once

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <Eigen/Sparse>

#include <array>
#include <memory>
#include <optional>
#include <utility>
#include <vector>

#include "d2vdb/field/Approximant.h"
#include "d2vdb/fit/detail/SensorMap.h"

namespace d2vdb::detail {

class SupernodalCholesky;

/// Rank-one terms alpha (u . c_k)^2 attached to the sensors of a SensorMap, with c_k the
/// displacements of sensor k's control points: u has order() * dimension entries, entry
/// j * dimension + a multiplying coordinate a of control point index(k, j). Sensor k's terms are
/// start[k] .. start[k + 1] - 1. A fitter uses them for second-order terms that no quadratic form
/// in the sensor position can express (e.g. how a footpoint's parameter follows the control
/// points); alpha may be negative.
/// Separable terms (a sensor's basis weights w_j times one direction t: u_{j d + a} = w_j t_a,
/// so (u . c_k)^2 = (t . sum_j w_j c_kj)^2, a move of the sensor's point along t) store only t:
/// `length` = dimension; the model then sums them like the forms, at a fraction of the cost.
struct RankOneTerms {
  int length = 0;                    ///< entries per vector u (order * dimension, or dimension)
  bool separable = false;            ///< vectors hold the directions t of separable terms
  std::vector<int> start{0};         ///< sensor count + 1 offsets into coefficients
  std::vector<double> coefficients;  ///< alpha per term
  std::vector<double> vectors;       ///< u (or t) per term, `length` entries each

  /// No terms for `sensorCount` sensors, vectors of `vectorLength` entries (separable: the
  /// dimension).
  void reset(int sensorCount, int vectorLength, bool separableTerms = false) {
    length = vectorLength;
    separable = separableTerms;
    start.assign(sensorCount + 1, 0);
    coefficients.clear();
    vectors.clear();
  }
  bool empty() const { return coefficients.empty(); }
};

/// One set of sensors of a QuadraticModel: their basis, one form per sensor, the weight every
/// form of the set gets (e.g. 1 / count for a mean) and optional rank-one terms (same weight).
/// The pointers must stay valid during the call that takes them.
struct SensorTerms {
  const SensorMap* basis = nullptr;
  const std::vector<QuadraticForm>* forms = nullptr;
  double weight = 1.0;
  const RankOneTerms* rankOne = nullptr;
};

/// Minimises over control-point displacements c (n points, `dimension` coordinates each)
///   m(c) = sum_s w_s sum_k [Q_sk(x_sk(P + c)) + r sum_t alpha_t (u_t . c_k)^2]
///          + sum_a (P + c)_a^T (S + sigma T) (P + c)_a + mu * m0 * |c|^2
///          (+ the optional step regulariser, setStepRegularizer())
/// over sensor sets s (SensorTerms, weight w_s), where Q_sk are the sensors' quadratic forms
/// (QuadraticForm: Q(x) = x^T A x - 2 b.x + c, world units), x_sk(P) the sensor positions of the
/// set's SensorMap, r the rank-one scale of the solve, S a fixed smoothing matrix and T a
/// second one scaled by sigma (setSmoothingScale(); both n x n, e.g. G2 and G1 of
/// SmoothingMatrix.h), mu the relative damping and m0 the mean diagonal of the undamped system
/// (so mu is dimensionless). A ridge of 1e-12 m0 keeps the system definite where no sensor and no
/// smoothing acts. In 2D (dimension 2) only the xy blocks of the forms enter and z stays 0.
///
/// assemble() sums the sensors' blocks once (in parallel over the sets' span groups; each group's
/// sensors in index order, or, for a knot cell whose sensors form a grid of parameters of a
/// tensor-product map, direction by direction (SensorMap::orderU()); the groups in set and span
/// order, so results are bitwise identical for any thread count); solveAssembled() then adds the
/// smoothing, rank-one scale, damping and regulariser and solves it, so that several of these
/// weights can be tried on one assembly. The system's sparsity pattern (control points sharing a
/// knot span, plus the smoothing and regulariser patterns) is kept between assemblies, and with it
/// the fill-reducing ordering and symbolic factorisation: an assembly whose sensors couple no new
/// pair of control points only scatters its blocks into the stored pattern. The system may be
/// indefinite (negative rank-one terms): lastSolvePositiveDefinite() tells. Solvers: a dense
/// Cholesky (pivoted LDLT when indefinite) for small systems whose pattern is dense anyway (at most
/// kDenseUnknowns unknowns and a twentieth of the entries); Eigen's SimplicialLDLT for other
/// systems of at most kSimplicialUnknowns unknowns (curves: narrow bands, little fill); a
/// supernodal sparse Cholesky (CHOLMOD) for larger ones (surfaces, whose two-dimensional nets fill
/// in), with the SimplicialLDLT when that finds the system indefinite. Every solver is serial, so
/// the result does not depend on the thread count.
class QuadraticModel {
 public:
  /// Largest system (control points x dimension) that may be factorised densely.
  static constexpr int kDenseUnknowns = 1200;
  /// Largest sparse system factorised by the simplicial LDLT rather than the supernodal Cholesky.
  static constexpr int kSimplicialUnknowns = 1200;

  /// `smoothing` and `scaledSmoothing` must be controlPointCount x controlPointCount (or empty,
  /// 0 x 0, for none), symmetric PSD. InputError for a dimension other than 2 or 3 or a smoothing
  /// matrix of the wrong size.
  QuadraticModel(int controlPointCount, int dimension, Eigen::SparseMatrix<double> smoothing,
                 Eigen::SparseMatrix<double> scaledSmoothing = {});
  ~QuadraticModel();
  QuadraticModel(const QuadraticModel&) = delete;
  QuadraticModel& operator=(const QuadraticModel&) = delete;

  /// assemble({{&basis, &forms, 1 / N}}, controlPoints), then solveAssembled(1, damping): the
  /// minimising displacement c for the mean of the forms, one vector per control point (z = 0 in
  /// 2D). `forms` has one entry per sensor of `basis`. Throws RuntimeFailure if the
  /// factorisation fails (a non-finite form).
  std::vector<Eigen::Vector3d> solve(const SensorMap& basis,
                                     const std::vector<QuadraticForm>& forms,
                                     const std::vector<Eigen::Vector3d>& controlPoints,
                                     double damping);

  /// Sums the sensor sets' forms and rank-one terms at the control points `controlPoints` (the
  /// expansion point P). InputError when a set's forms or rank-one terms do not match its basis
  /// or its basis another control-point count.
  void assemble(const std::vector<SensorTerms>& terms,
                const std::vector<Eigen::Vector3d>& controlPoints);

  /// The stationary point of m for the last assembly with rank-one scale r = `rankOneScale` and
  /// relative damping mu = `damping` (the minimiser when the system is positive definite).
  /// RuntimeFailure when nothing was assembled, the factorisation fails or the step is not
  /// finite.
  std::vector<Eigen::Vector3d> solveAssembled(double rankOneScale, double damping);

  /// As solveAssembled(), but only when the system is positive definite: otherwise nothing (and
  /// lastSolvePositiveDefinite() is false), without the second factorisation that the stationary
  /// point of an indefinite large system costs.
  std::optional<std::vector<Eigen::Vector3d>> minimizeAssembled(double rankOneScale,
                                                                double damping);

  /// m(0) - m(c) for the last assembly and rank-one scale, without the damping and
  /// step-regulariser terms: the decrease of the modelled objective the displacement `step`
  /// promises.
  double predictedDecrease(const std::vector<Eigen::Vector3d>& step) const;

  /// H^-1 (sigma T P) with the last factorisation (H its system): how far the scaled smoothing
  /// term has moved the model's minimiser, per control point (z = 0 in 2D). Zero before any
  /// solve or without a scaled smoothing matrix.
  std::vector<Eigen::Vector3d> scaledSmoothingShift() const;

  /// Sets sigma (finite, >= 0; InputError otherwise) for the following solves and
  /// smoothingEnergy(). Default 1.
  void setSmoothingScale(double scale);
  double smoothingScale() const { return smoothingScale_; }

  /// Adds the step regulariser rho * m0 / g0 * sum_a c_a^T R c_a to m(c), with R symmetric PSD
  /// (n x n; e.g. the bending Gram matrix, so that only rough displacements are damped and the
  /// minimiser of the fit is not biased) and g0 its mean diagonal. rho = 0 removes it.
  /// InputError for a wrong size or negative rho.
  void setStepRegularizer(Eigen::SparseMatrix<double> regularizer, double rho);

  /// sum_a P_a^T (S + sigma T) P_a: the smoothing energy of the control points.
  double smoothingEnergy(const std::vector<Eigen::Vector3d>& controlPoints) const;

  /// Whether the last solve's system was positive definite (all LDL^T pivots positive).
  bool lastSolvePositiveDefinite() const { return factorizations_[current_].positiveDefinite; }

  int dimension() const { return dimension_; }

 private:
  /// One assembly: every span group of every sensor set, the sums of its forms and rank-one
  /// terms, and where its blocks go in the pattern (QuadraticModel.cc).
  struct Assembly;
  /// Looks up where `group`'s blocks go in the pattern; false when one lies outside it.
  bool findRanks(Assembly& assembly, std::size_t group) const;
  /// Resets the last assembly's values and right-hand sides to the sums of `assembly`.
  void scatter(const Assembly& assembly);
  /// Adds local block column b of `group`'s sums into control point `column`'s column of the
  /// values and its rows of the right-hand sides.
  void scatterBlockColumn(const Assembly& assembly, std::size_t group, int b, int column);
  /// Position in the control-point pattern of row i within column j, or -1 when absent.
  int patternRank(int row, int column) const;
  /// Rebuilds the pattern as the union of the current one, `pairs` (row, column of control
  /// points), the smoothing matrices, the regulariser and the diagonal; the solver must
  /// re-analyse.
  void rebuildPattern(const std::vector<std::pair<int, int>>& pairs);
  /// Index into system_'s values of unknown (row * d + r, column * d + c), given the rank of row
  /// in the column.
  int valueIndex(int rank, int column, int r, int c) const {
    return static_cast<int>(system_.outerIndexPtr()[column * dimension_ + c]) + rank * dimension_ +
           r;
  }
  /// Value indices of every entry of `matrix` (an n x n matrix inside the pattern) for each
  /// coordinate, in `matrix`'s storage order: entry e, coordinate a at [e * d + a].
  std::vector<int> valueIndicesOf(const Eigen::SparseMatrix<double>& matrix) const;
  /// Adds scale * matrix (per coordinate) into `values` (system_'s layout) at `indices`.
  void addScaled(const Eigen::SparseMatrix<double>& matrix, const std::vector<int>& indices,
                 double scale, double* values) const;
  /// The control points stacked per coordinate (unknown i * d + a).
  Eigen::VectorXd stacked(const std::vector<Eigen::Vector3d>& controlPoints) const;
  /// The inverse of stacked().
  std::vector<Eigen::Vector3d> unstacked(const Eigen::VectorXd& vector) const;
  /// values[e] = the last assembly's forms plus rankOneScale times its rank-one terms plus the
  /// smoothing, in system_'s layout.
  void hessianValues(double rankOneScale, double* values) const;
  /// Fills system_ with the system of the last assembly for `rankOneScale` and `damping` (the
  /// Hessian plus ridge, damping and regulariser) and returns its right-hand side r - H P.
  Eigen::VectorXd loadSystem(double rankOneScale, double damping);
  /// solveAssembled() (`indefiniteToo`) or minimizeAssembled().
  std::optional<std::vector<Eigen::Vector3d>> solveSystem(double rankOneScale, double damping,
                                                          bool indefiniteToo);

  int controlPointCount_;
  int dimension_;
  Eigen::SparseMatrix<double> smoothing_;
  Eigen::SparseMatrix<double> scaledSmoothing_;
  double smoothingScale_ = 1.0;
  Eigen::SparseMatrix<double> regularizer_;
  double regularizerWeight_ = 0.0;
  // Control-point pattern (compressed columns, sorted rows) and the system over the unknowns
  // that expands it (each control-point entry becomes a d x d block).
  std::vector<int> patternStart_;
  std::vector<int> patternRows_;
  Eigen::SparseMatrix<double> system_;
  std::vector<int> smoothingIndices_;
  std::vector<int> scaledSmoothingIndices_;
  std::vector<int> regularizerIndices_;
  std::vector<int> diagonalIndices_;
  // The last assembly: the forms' and the rank-one terms' matrices (system_'s layout) and
  // right-hand sides, and the expansion point.
  bool assembled_ = false;
  std::vector<double> formValues_;
  std::vector<double> rankOneValues_;
  Eigen::VectorXd formRight_;
  Eigen::VectorXd rankOneRight_;
  Eigen::VectorXd expansionPoint_;
  double rankOneScale_ = 1.0;
  /// What decides the system of a solve of the current assembly.
  struct SolveKey {
    double rankOneScale = 0.0;
    double damping = 0.0;
    double smoothingScale = 0.0;
    double regularizerWeight = 0.0;
    bool operator==(const SolveKey& other) const {
      return rankOneScale == other.rankOneScale && damping == other.damping &&
             smoothingScale == other.smoothingScale && regularizerWeight == other.regularizerWeight;
    }
  };
  enum class Solver { none, denseCholesky, denseLdlt, sparseLdlt, supernodalCholesky };
  /// One factorised system of the current assembly.
  struct Factorization {
    SolveKey key;
    Eigen::VectorXd residual;  ///< its right-hand side
    bool valid = false;        ///< holds the factorisation of `key`'s system
    bool positiveDefinite = true;
    Solver solverUsed = Solver::none;
    bool analyzed = false;      ///< the supernodal factorisation has the current pattern
    bool ldltAnalyzed = false;  ///< the LDLT factorisation has the current pattern
    std::unique_ptr<SupernodalCholesky> cholesky;
    Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt;
    Eigen::LLT<Eigen::MatrixXd> denseCholesky;
    Eigen::LDLT<Eigen::MatrixXd> denseLdlt;
    /// Factorises `system` (`unknowns` square) with the solver that its size and pattern call for
    /// and sets positiveDefinite; a large system found indefinite gets the LDLT only with
    /// `indefiniteToo`.
    void factorize(const Eigen::SparseMatrix<double>& system, int unknowns, bool indefiniteToo);
    void factorizeDense(const Eigen::SparseMatrix<double>& system);
    void factorizeSparse(const Eigen::SparseMatrix<double>& system, int unknowns,
                         bool indefiniteToo);
    /// x with A x = right for this factorisation's system A.
    Eigen::VectorXd solve(const Eigen::VectorXd& right) const;
    /// Forgets the factorisation and, with `pattern`, the analysis of the pattern.
    void reset(bool pattern);
  };
  /// The last two factorisations: a system that turns out indefinite (a refused second-order
  /// step) does not evict the one before it, which the fallback step then reuses.
  std::array<Factorization, 2> factorizations_;
  std::size_t current_ = 0;  ///< the slot of the last solve
};

}  // namespace d2vdb::detail
