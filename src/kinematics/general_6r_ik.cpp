#include "robcal/kinematics/general_6r_ik.hpp"

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <Eigen/LU>
#include <Eigen/QR>
#include <Eigen/SVD>
#include <algorithm>
#include <bit>
#include <cmath>
#include <complex>
#include <limits>
#include <numbers>
#include <type_traits>
#include <vector>

#include "ik_sink.hpp"
#include "robcal/model/parameters.hpp"

namespace robcal {

/// What the elimination takes from the three kept joints alone (docs/method/02-frames.md §7).
struct General6rElimination {
  /// Left sides times (1 + x4²)(1 + x5²): for each θ3 term (1, cos θ3, sin θ3) the coefficients
  /// of x4^i·x5^j, column 3i + j.
  std::array<Eigen::Matrix<double, 14, 9>, 3> left;
  /// Y = [top; bottom], an orthonormal basis of the companion space orthogonal to the spurious
  /// eigenvectors (x3 = ±i), and topᵀ·bottom.
  Eigen::Matrix<double, 12, Eigen::Dynamic, 0, 12, 24> top, bottom;
  Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, 24, 24> top_t_bottom;
};

namespace {

using Equations = Eigen::Matrix<double, 14, 1>;
using Matrix12 = Eigen::Matrix<double, 12, 12>;
using Vector12 = Eigen::Matrix<double, 12, 1>;
using Angles = std::array<double, kJointCount>;
/// The companion matrix with the spurious eigenvalues deflated (16×16 on every arm tried).
using Companion = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, 24, 24>;
using CompanionBasis = Eigen::Matrix<double, 12, Eigen::Dynamic, 0, 12, 24>;

/// Interpolation nodes 0, 2π/3, 4π/3: a degree-one trigonometric polynomial is fixed by them.
constexpr double kNodes[3] = {0.0, 2.0 * std::numbers::pi / 3.0, 4.0 * std::numbers::pi / 3.0};
/// Shifts φ of the half-angle substitutions (θ4, θ5 fixed; θ3 the first of these whose leading
/// coefficient is well conditioned). Arbitrary values, away from the 0 and ±90° of real robots.
constexpr double kShift4 = 0.7137, kShift5 = -1.2911;
constexpr double kShifts3[4] = {0.4123, 1.9371, -2.4417, -0.9853};
/// Leading coefficient rcond below which the next θ3 shift is tried.
constexpr double kWellConditioned = 1e-8;
/// An eigenvalue is a real candidate when |Im| ≤ this · (1 + |λ|); near-double roots come out
/// as complex pairs this close, and Newton decides.
constexpr double kRealEigenvalue = 1e-4;
/// Roots of x3 closer than this · (1 + |x3|) are treated as one multiple root; clustering two
/// distinct roots this close costs nothing (Newton separates them from the cluster's start).
constexpr double kSameRoot = 1e-4;
/// A diagonal entry of the pivoted QR of M(x3)ᵀ below this fraction of the largest marks one
/// more dimension of M's null space.
constexpr double kNullSpace = 1e-7;
/// The largest multiplicity handled (two solutions per shared angle on the CRX).
constexpr int kMaxCluster = 4;
/// A root with another eigenvalue within this · (1 + |x3|) may be part of a multiple root that
/// rounding split wider than kSameRoot: on robots whose solutions pair up (spherical-wrist-like
/// twins sharing x3) the double root is defective and its eigenvalues spread as ε^(1/4), up to
/// 1e-2 (Stäubli TX2-60, Doosan M1013, CRX near θ5 = 0).
constexpr double kCrowded = 3e-2;
/// A lone root whose solutions all lie this close (· (1 + |x3|)) to its eigenvalue is simple:
/// rounding moves a simple root's eigenvalue by about ε times its condition, while a multiple
/// root split by rounding is off by √ε or more (the twins the crowded search finds, on 400,000
/// configurations of the four general 6R arms, were at 1e-10 or farther; 1e-12 to 1e-15 is usual).
constexpr double kSimpleRoot = 1e-12;
/// A singular value of the left sides at x3 = i below this fraction of the largest spans a
/// spurious eigenvector (they are 1e-16 relative, the others above 1e-3, on the arms tried).
constexpr double kSpuriousNull = 1e-10;
/// Acceptance of a polished candidate, and the distance below which two are the same.
constexpr double kAcceptPositionMm = 1e-9;
constexpr double kAcceptOrientationRad = 1e-11;
constexpr double kSameSolutionRad = 1e-6;
/// A candidate starting this close to a solution already found would be polished to it (another
/// solution within kSameSolutionRad is merged with it anyway, one farther lies outside Newton's
/// path): it is that solution, unpolished. The twin search's null space at a solution's own x3
/// returns that solution again, 1e-10 close (a quarter of the CRX's candidates).
constexpr double kSameStartRad = 1e-8;
constexpr int kNewtonIterations = 20;
/// An accepted Newton step this small (rad, largest joint) leaves, at a well-conditioned root, an
/// error of its square times the curvature, below rounding: the polish stops there without one
/// more step to confirm (beside a near-double root the error is about one step: refine_extended).
constexpr double kConvergedStepRad = 1e-10;

Pose<double> rot_z(double theta) {
  const double c = std::cos(theta), s = std::sin(theta);
  Pose<double> out;
  out.R << c, -s, 0, s, c, 0, 0, 0, 1;
  return out;
}

Pose<double> scaled(const Pose<double>& pose, double scale) {
  return {pose.R, pose.p / scale};
}

/// The 14 equations of the header from the origin p and z axis l of one side.
Equations equations(const Pose<double>& side) {
  const Eigen::Vector3d p = side.p, l = side.R.col(2);
  const double pp = p.dot(p), pl = p.dot(l);
  Equations e;
  e << l, p, pp, pl, p.cross(l), l * pp - 2.0 * pl * p;
  return e;
}

/// Weights turning values at kNodes into coefficients of {1, cos θ, sin θ}.
const Eigen::Matrix3d kNodeWeights =
    (Eigen::Matrix3d() << 1.0 / 3, 1.0 / 3, 1.0 / 3, 2.0 / 3, -1.0 / 3, -1.0 / 3, 0.0,
     1.0 / std::sqrt(3.0), -1.0 / std::sqrt(3.0))
        .finished();

/// (1 + x²)·(1, cos θ, sin θ) as coefficients of (1, x, x²), θ = φ + 2·atan(x): row = power.
Eigen::Matrix3d half_angle(double phi) {
  const double c = std::cos(phi), s = std::sin(phi);
  Eigen::Matrix3d H;
  H << 1, c, s, 0, -2 * s, 2 * c, 1, -c, -s;
  return H;
}

/// The 14×12 equations of M(x3) before the θ1θ2 elimination: the 9 monomials x4^i·x5^j of
/// `coeff` (column 3i + j), and the same equations times x4 on 12 monomials.
template <typename Out, typename In>
void place_twice(Out&& out, const In& coeff) {
  out.template block<14, 9>(0, 0) = coeff;
  out.template block<14, 9>(14, 3) = coeff;
}

/// The elimination's constants from the kept links K3, K4, K5 (scaled lengths).
General6rElimination kept_joints_elimination(const Pose<double>& K3, const Pose<double>& K4,
                                             const Pose<double>& K5) {
  const Eigen::Matrix3d& W = kNodeWeights;
  // Left sides at the 27 node triples, interpolated over {1, cos, sin} of θ3, θ4, θ5.
  Eigen::Matrix<double, 14, 27> values, left = Eigen::Matrix<double, 14, 27>::Zero();
  for (int k3 = 0; k3 < 3; ++k3)
    for (int k4 = 0; k4 < 3; ++k4)
      for (int k5 = 0; k5 < 3; ++k5)
        values.col(9 * k3 + 3 * k4 + k5) =
            equations(rot_z(kNodes[k3]) * K3 * rot_z(kNodes[k4]) * K4 * rot_z(kNodes[k5]) * K5);
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b)
      for (int c = 0; c < 3; ++c)
        for (int k3 = 0; k3 < 3; ++k3)
          for (int k4 = 0; k4 < 3; ++k4)
            for (int k5 = 0; k5 < 3; ++k5)
              left.col(9 * a + 3 * b + c) +=
                  W(a, k3) * W(b, k4) * W(c, k5) * values.col(9 * k3 + 3 * k4 + k5);
  // Half-angle polynomials in x4, x5 for each trigonometric term a of θ3.
  const Eigen::Matrix3d H4 = half_angle(kShift4), H5 = half_angle(kShift5);
  General6rElimination e;
  for (int a = 0; a < 3; ++a) {
    e.left[a].setZero();
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        for (int b = 0; b < 3; ++b)
          for (int c = 0; c < 3; ++c)
            e.left[a].col(3 * i + j) += H4(i, b) * H5(j, c) * left.col(9 * a + 3 * b + c);
  }
  // At x3 = ±i the constant θ3 term, hence the whole right side, vanishes with (1 + x3²):
  // M(i) = 2·e^(−iφ3)·Uᵀ(L_cos + i·L_sin) whatever the pose. The null vectors v = a + i·b of the
  // left sides' L_cos + i·L_sin give the companion's spurious eigenvectors [v; i·v], whose real
  // span is {[a; −b]}: (a, b) the null space of the real form [[Re, −Im], [Im, Re]].
  Eigen::Matrix<double, 56, 24> real_form = Eigen::Matrix<double, 56, 24>::Zero();
  place_twice(real_form.block<28, 12>(0, 0), e.left[1]);
  place_twice(real_form.block<28, 12>(28, 12), e.left[1]);
  place_twice(real_form.block<28, 12>(0, 12), -e.left[2]);
  place_twice(real_form.block<28, 12>(28, 0), e.left[2]);
  const Eigen::JacobiSVD<Eigen::Matrix<double, 56, 24>> svd(real_form, Eigen::ComputeFullV);
  int rank = 0;
  while (rank < 24 && svd.singularValues()[rank] > kSpuriousNull * svd.singularValues()[0]) ++rank;
  e.top = svd.matrixV().topRows<12>().leftCols(rank);
  e.bottom = -svd.matrixV().bottomRows<12>().leftCols(rank);
  e.top_t_bottom = e.top.transpose() * e.bottom;
  return e;
}

/// The elementary reflector I − τ·u·uᵀ, u = [1; ess], that maps x to (β, 0, …) (Eigen's
/// makeHouseholder for a real vector, inlined: it is the inner loop of the eigenvalue QR).
/// Returns β; τ = 0 when x's tail is already zero.
template <int N>
double make_reflector(const Eigen::Matrix<double, N, 1>& x, Eigen::Matrix<double, N - 1, 1>& ess,
                      double& tau) {
  const double tail = x.template tail<N - 1>().squaredNorm();
  if (tail <= std::numeric_limits<double>::min()) {
    tau = 0;
    ess.setZero();
    return x[0];
  }
  double beta = std::sqrt(x[0] * x[0] + tail);
  if (x[0] >= 0) beta = -beta;
  ess = x.template tail<N - 1>() / (x[0] - beta);
  tau = (beta - x[0]) / beta;
  return beta;
}

/// An elementary reflector I − τ·u·uᵀ, u = [1; ess], on rows and columns r..r+N−1 of T: from the
/// left on columns `left_from`..`left_to`, then from the right on rows `right_from`..`right_to`.
template <int N>
void reflect(Companion& T, Eigen::Index r, const Eigen::Matrix<double, N - 1, 1>& ess, double tau,
             Eigen::Index left_from, Eigen::Index left_to, Eigen::Index right_from,
             Eigen::Index right_to) {
  for (Eigen::Index j = left_from; j <= left_to; ++j) {
    double t = T(r, j);
    for (int i = 1; i < N; ++i) t += ess[i - 1] * T(r + i, j);
    t *= tau;
    T(r, j) -= t;
    for (int i = 1; i < N; ++i) T(r + i, j) -= ess[i - 1] * t;
  }
  for (Eigen::Index i = right_from; i <= right_to; ++i) {
    double t = T(i, r);
    for (int k = 1; k < N; ++k) t += T(i, r + k) * ess[k - 1];
    t *= tau;
    T(i, r) -= t;
    for (int k = 1; k < N; ++k) T(i, r + k) -= t * ess[k - 1];
  }
}

/// The deflated companion's Hessenberg form (divided by its largest entry, `scale`) and, once
/// companion_eigenvalues succeeded, its `count` eigenvalues.
struct CompanionSpectrum {
  Eigen::HessenbergDecomposition<Companion> hessenberg;
  double scale = 0;
  std::array<std::complex<double>, 24> eigenvalues;
  int count = 0;
};

/// The eigenvalues of the deflated companion, eigenvalues only (docs/method/02-frames.md §7):
/// Eigen's Hessenberg reduction, then the Francis double-shift QR of Eigen's RealSchur (the same
/// shifts, exceptional shifts, deflation test and iteration limit) with each step applied to the
/// active window alone, as LAPACK's dlahqr does without the Schur form: the columns right of the
/// window and the rows above it are read only by the Schur vectors and the full Schur form,
/// which are not wanted. In the order of the quasi-triangular form, a complex pair + then −;
/// false when the QR does not converge or an eigenvalue is not finite.
bool companion_eigenvalues(const Companion& C, CompanionSpectrum& spectrum) {
  using Eigen::Index;
  using std::abs;
  constexpr double kEps = std::numeric_limits<double>::epsilon();
  const Index n = C.rows();
  spectrum.count = 0;
  const double largest = C.cwiseAbs().maxCoeff();
  if (!std::isfinite(largest)) return false;
  const double scale = spectrum.scale = largest > 0 ? largest : 1.0;
  std::array<std::complex<double>, 24>& lambda = spectrum.eigenvalues;
  Companion T = spectrum.hessenberg.compute(C / scale).matrixH();
  double norm = 0;
  for (Index j = 0; j < n; ++j) norm += T.col(j).head(std::min(n, j + 2)).cwiseAbs().sum();
  const double negligible = std::max(norm * kEps * kEps, std::numeric_limits<double>::min());
  Index iu = n - 1;
  int iter = 0, total = 0;
  double exshift = 0;
  while (iu >= 0) {
    Index il = iu;  // the window: T(il, il − 1) negligible
    for (; il > 0; --il)
      if (abs(T(il, il - 1)) <=
          std::max((abs(T(il - 1, il - 1)) + abs(T(il, il))) * kEps, negligible))
        break;
    if (il == iu) {
      lambda[iu] = (T(iu, iu) + exshift) * scale;
      --iu;
      iter = 0;
      continue;
    }
    if (il == iu - 1) {  // a 2×2 block: two real eigenvalues (Givens-triangularized) or a pair
      Eigen::Matrix2d B = T.block<2, 2>(iu - 1, iu - 1);
      const double p = 0.5 * (B(0, 0) - B(1, 1)), q = p * p + B(1, 0) * B(0, 1);
      B.diagonal().array() += exshift;
      if (q >= 0) {
        const double z = std::sqrt(q);
        Eigen::JacobiRotation<double> rot;
        rot.makeGivens(p >= 0 ? p + z : p - z, B(1, 0));
        B.applyOnTheLeft(0, 1, rot.adjoint());
        B.applyOnTheRight(0, 1, rot);
        lambda[iu - 1] = B(0, 0) * scale;
        lambda[iu] = B(1, 1) * scale;
      } else {
        B *= scale;
        const double h = 0.5 * (B(0, 0) - B(1, 1));
        const double big = std::max(abs(h), std::max(abs(B(1, 0)), abs(B(0, 1))));
        const double hb = h / big,
                     z = big * std::sqrt(abs(hb * hb + (B(1, 0) / big) * (B(0, 1) / big)));
        lambda[iu - 1] = {B(1, 1) + h, z};
        lambda[iu] = {B(1, 1) + h, -z};
      }
      iu -= 2;
      iter = 0;
      continue;
    }
    // Shift (Eigen's computeShift: Wilkinson's exceptional shift at 10 iterations, MATLAB's at 30).
    Eigen::Vector3d shift(T(iu, iu), T(iu - 1, iu - 1), T(iu, iu - 1) * T(iu - 1, iu));
    if (iter == 10) {
      exshift += shift[0];
      for (Index i = 0; i <= iu; ++i) T(i, i) -= shift[0];
      const double s = abs(T(iu, iu - 1)) + abs(T(iu - 1, iu - 2));
      shift << 0.75 * s, 0.75 * s, -0.4375 * s * s;
    }
    if (iter == 30) {
      double s = (shift[1] - shift[0]) / 2.0;
      s = s * s + shift[2];
      if (s > 0) {
        s = std::sqrt(s);
        if (shift[1] < shift[0]) s = -s;
        s = shift[0] - shift[2] / (s + (shift[1] - shift[0]) / 2.0);
        exshift += s;
        for (Index i = 0; i <= iu; ++i) T(i, i) -= s;
        shift.setConstant(0.964);
      }
    }
    ++iter;
    if (++total > 40 * n) return false;
    // Where the step starts (two consecutive small subdiagonals) and its first reflector.
    Eigen::Vector3d v;
    Index im = iu - 2;
    for (;; --im) {
      const double Tmm = T(im, im), r = shift[0] - Tmm, s = shift[1] - Tmm;
      v << (r * s - shift[2]) / T(im + 1, im) + T(im, im + 1), T(im + 1, im + 1) - Tmm - r - s,
          T(im + 2, im + 1);
      if (im == il) break;
      const double lhs = T(im, im - 1) * (abs(v[1]) + abs(v[2]));
      const double rhs = v[0] * (abs(T(im - 1, im - 1)) + abs(Tmm) + abs(T(im + 1, im + 1)));
      if (abs(lhs) < kEps * rhs) break;
    }
    for (Index k = im; k <= iu - 2; ++k) {
      if (k > im) v = T.block<3, 1>(k, k - 1);
      Eigen::Vector2d ess;
      double tau;
      const double beta = make_reflector<3>(v, ess, tau);
      if (beta == 0 || tau == 0) continue;  // the identity: nothing to apply
      if (k > im)
        T(k, k - 1) = beta;
      else if (k > il)
        T(k, k - 1) *= 1 - tau;  // dlahqr: the similarity's effect on the entry left of the bulge
      reflect<3>(T, k, ess, tau, k, iu, il, std::min(iu, k + 3));
    }
    Eigen::Matrix<double, 1, 1> ess;
    double tau;
    const double beta =
        make_reflector<2>(Eigen::Vector2d(T(iu - 1, iu - 2), T(iu, iu - 2)), ess, tau);
    if (beta != 0) {
      T(iu - 1, iu - 2) = beta;
      reflect<2>(T, iu - 1, ess, tau, iu - 1, iu, il, iu);
    }
    for (Index i = im + 2; i <= iu; ++i) {  // rounding pollution below the subdiagonal
      T(i, i - 2) = 0;
      if (i > im + 2) T(i, i - 3) = 0;
    }
  }
  if (!std::all_of(lambda.begin(), lambda.begin() + n,
                   [](const std::complex<double>& l) { return std::isfinite(std::abs(l)); }))
    return false;
  spectrum.count = static_cast<int>(n);
  return true;
}

/// The companion's eigenvector for its real eigenvalue `lambda`, by inverse iteration on the
/// Hessenberg form H (LAPACK's dlaein): Gaussian elimination of H − λ·I with partial pivoting
/// between neighbouring rows (O(n²)), a first solve of U·x = 1, a second of (H − λ·I)·x = x, a
/// pivot that rounding made zero replaced by ε·‖H‖; then back to the companion's coordinates by
/// the Hessenberg reduction's Q.
Eigen::Matrix<double, Eigen::Dynamic, 1, 0, 24, 1> companion_eigenvector(
    const CompanionSpectrum& spectrum, double lambda) {
  using Eigen::Index;
  using Vector = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, 24, 1>;
  const Index n = spectrum.hessenberg.packedMatrix().rows();
  Companion A = spectrum.hessenberg.matrixH();
  A.diagonal().array() -= lambda / spectrum.scale;
  const double tiny = std::numeric_limits<double>::epsilon() * A.cwiseAbs().maxCoeff();
  std::array<bool, 24> swapped{};
  std::array<double, 24> factor{};
  for (Index k = 0; k + 1 < n; ++k) {
    swapped[k] = std::abs(A(k + 1, k)) > std::abs(A(k, k));
    if (swapped[k]) A.row(k).tail(n - k).swap(A.row(k + 1).tail(n - k));
    if (A(k, k) == 0) A(k, k) = tiny;
    factor[k] = A(k + 1, k) / A(k, k);
    A.row(k + 1).tail(n - k - 1) -= factor[k] * A.row(k).tail(n - k - 1);
  }
  if (A(n - 1, n - 1) == 0) A(n - 1, n - 1) = tiny;
  const auto U = A.triangularView<Eigen::Upper>();
  Vector x = U.solve(Vector::Ones(n));
  x /= x.cwiseAbs().maxCoeff();
  for (Index k = 0; k + 1 < n; ++k) {
    if (swapped[k]) std::swap(x[k], x[k + 1]);
    x[k + 1] -= factor[k] * x[k];
  }
  U.solveInPlace(x);
  return spectrum.hessenberg.matrixQ() * (x / x.norm());
}

/// Pose of the chain's flange and each joint's frame, axis origin and direction.
template <typename T>
struct Frames {
  Pose<T> flange;
  std::array<Vector3<T>, kJointCount> origin, axis;
  std::array<Pose<T>, kJointCount> frame;
};

/// F·Rz(θ): the x and y axes turn, the z axis and the origin stay (cheaper than the product).
template <typename T>
void turn_about_z(Pose<T>& F, T theta) {
  using std::cos;
  using std::sin;
  const T c = cos(theta), s = sin(theta);
  const Vector3<T> x = F.R.col(0);
  F.R.col(0) = c * x + s * F.R.col(1);
  F.R.col(1) = c * F.R.col(1) - s * x;
}

template <typename T>
Pose<T> cast_pose(const Pose<double>& pose) {
  if constexpr (std::is_same_v<T, double>)
    return pose;
  else
    return {pose.R.cast<T>(), pose.p.cast<T>()};
}

/// The chain B·Rz(θ1)·K1 ⋯ K5·Rz(θ6) in T (double, or long double for the refinement).
template <typename T>
Frames<T> forward(const General6rGeometry& g, const std::array<T, kJointCount>& theta) {
  Frames<T> f;
  Pose<T> F = cast_pose<T>(g.base);
  for (int i = 0; i < kJointCount; ++i) {
    turn_about_z(F, theta[i]);
    f.frame[i] = F;
    f.origin[i] = F.p;
    f.axis[i] = F.R.col(2);
    if (i < kJointCount - 1) F = F * cast_pose<T>(g.link[i]);
  }
  f.flange = F;
  return f;
}

double wrap(double angle) {
  return std::remainder(angle, 2.0 * std::numbers::pi);
}

/// The pose error (position mm, rotation vector rad) of the chain's flange against `target`
/// and the geometric Jacobian of the joints, in T.
template <typename T>
void pose_error_and_jacobian(const Frames<T>& f, const Pose<T>& target, Eigen::Matrix<T, 6, 1>& e,
                             Eigen::Matrix<T, 6, 6>& J) {
  e.template head<3>() = target.p - f.flange.p;
  const Eigen::AngleAxis<T> aa(Eigen::Matrix<T, 3, 3>(target.R * f.flange.R.transpose()));
  e.template tail<3>() = aa.angle() * aa.axis();
  for (int i = 0; i < kJointCount; ++i) {
    J.template block<3, 1>(0, i) = f.axis[i].cross(f.flange.p - f.origin[i]);
    J.template block<3, 1>(3, i) = f.axis[i];
  }
}

/// Where the Jacobian is this close to singular (smallest to largest pivot of its LU, lengths
/// scaled), the root is near-double (two solutions 1e-6 rad apart on a CRX-10iA/L): Newton
/// converges only linearly there, each step halving the distance while the error falls by 4, so
/// the factor-4 stop ends it up to 1e-6 rad short, with the pose already within 1e-10 mm; the
/// double chain's rounding (1e-13 mm over 4e-5 mm/rad) would leave 2e-9 rad more. Newton goes
/// on in long double (docs/method/02-frames.md §7).
constexpr double kIllConditionedPivots = 1e-6;
constexpr int kExtendedIterations = 6;
constexpr double kExtendedStepRad = 1e-11;

/// Newton steps in long double from an accepted `theta` beside a near-double root. Kept when they
/// converge (a last step below kExtendedStepRad) while every step is at most 3/4 of the one before
/// and the whole move stays within 4 first steps (a geometric series of ratio 3/4): Newton
/// contracting onto a root near the start, not wandering. From a start between two twins it
/// still reaches whichever is nearer; the solutions are then merged at kSameSolutionRad as
/// before, so their number does not change, but which twin represents the pair may.
/// Where long double is double (not on Debian's x86-64 and aarch64), it changes nothing.
void refine_extended(const General6rGeometry& g, const Pose<double>& target, Angles& theta) {
  using Extended = long double;
  std::array<Extended, kJointCount> x;
  for (int i = 0; i < kJointCount; ++i) x[i] = theta[i];
  const Pose<Extended> goal = cast_pose<Extended>(target);
  Eigen::Matrix<Extended, 6, 1> e;
  Eigen::Matrix<Extended, 6, 6> J;
  Extended last_step = std::numeric_limits<Extended>::infinity(), first_step = 0;
  for (int it = 0; it < kExtendedIterations && last_step > kExtendedStepRad; ++it) {
    pose_error_and_jacobian(forward(g, x), goal, e, J);
    const Eigen::Matrix<Extended, 6, 1> step = J.colPivHouseholderQr().solve(e);
    if (!step.allFinite()) return;
    const Extended size = step.cwiseAbs().maxCoeff();
    if (it == 0)
      first_step = size;
    else if (size > 0.75 * last_step)
      return;  // not contracting towards a root
    for (int i = 0; i < kJointCount; ++i) x[i] += step[i];
    last_step = size;
  }
  if (last_step > kExtendedStepRad) return;
  for (int i = 0; i < kJointCount; ++i)
    if (std::abs(x[i] - Extended{theta[i]}) > 4 * first_step + kExtendedStepRad) return;
  for (int i = 0; i < kJointCount; ++i) theta[i] = static_cast<double>(x[i]);
}

/// Newton on the exact chain from `theta`; true when it reproduces `target` within the
/// acceptance tolerances.
bool polish(const General6rGeometry& g, const Pose<double>& target, Angles& theta) {
  double previous = std::numeric_limits<double>::infinity(), last_step = previous;
  Vector6d e;
  Matrix6d J;
  for (int it = 0;; ++it) {
    pose_error_and_jacobian(forward(g, theta), target, e, J);
    const bool accepted =
        e.head<3>().norm() <= kAcceptPositionMm && e.tail<3>().norm() <= kAcceptOrientationRad;
    // Once accepted, go on while a step still gains (quadratic convergence down to rounding),
    // unless the last step was already so small that the next would be below rounding.
    const double error = e.head<3>().norm() / g.length_scale + e.tail<3>().norm();
    if (it == kNewtonIterations ||
        (accepted && (error > 0.25 * previous || last_step <= kConvergedStepRad))) {
      if (accepted) {
        J.topRows<3>() /= g.length_scale;
        const Vector6d pivots = J.partialPivLu().matrixLU().diagonal().cwiseAbs();
        if (pivots.minCoeff() < kIllConditionedPivots * pivots.maxCoeff())
          refine_extended(g, target, theta);
      }
      return accepted;
    }
    previous = error;
    Vector6d step = J.partialPivLu().solve(e);
    if (!step.allFinite()) return accepted;
    const double largest = step.cwiseAbs().maxCoeff();
    if (largest > 0.3) step *= 0.3 / largest;  // far from a root: stay in its basin
    last_step = std::min(largest, 0.3);
    for (int i = 0; i < kJointCount; ++i) theta[i] += step[i];
  }
}

/// θ2, then θ1 and θ6, once θ3, θ4, θ5 are known (scaled lengths): the origin g and z axis n
/// of K2·Rz(θ3)·K3·Rz(θ4)·K4·Rz(θ5)·K5 must map by Rz(θ1)·K1·Rz(θ2) onto those of T'.
void solve_first_and_last(const std::array<Pose<double>, 5>& K, const Pose<double>& Tp,
                          Angles& theta) {
  const Pose<double> G =
      K[1] * rot_z(theta[2]) * K[2] * rot_z(theta[3]) * K[3] * rot_z(theta[4]) * K[4];
  const Eigen::Vector3d t = Tp.p, l = Tp.R.col(2);
  // u = K1·Rz(θ2)·g, w = K1·Rz(θ2)·n; the invariants of Rz(θ1) give five equations of degree
  // one in θ2: u_z, w_z, u·u, u·w, (u×w)_z equal those of t, l.
  auto residuals = [&](double theta2) {
    const Pose<double> M = K[0] * rot_z(theta2) * G;
    const Eigen::Vector3d u = M.p, w = M.R.col(2);
    Eigen::Matrix<double, 5, 1> r;
    r << u.z() - t.z(), w.z() - l.z(), u.dot(u) - t.dot(t), u.dot(w) - t.dot(l),
        u.cross(w).z() - t.cross(l).z();
    return r;
  };
  Eigen::Matrix<double, 5, 3> values, A;
  for (int k = 0; k < 3; ++k) values.col(k) = residuals(kNodes[k]);
  const Eigen::Matrix<double, 5, 3> coeff = values * kNodeWeights.transpose();  // 1, cos, sin
  A << coeff.col(1), coeff.col(2), coeff.col(0);
  for (int r = 0; r < 5; ++r) {
    const double n = A.row(r).norm();
    if (n > 0) A.row(r) /= n;
  }
  const Eigen::JacobiSVD<Eigen::Matrix<double, 5, 3>> svd(A, Eigen::ComputeFullV);
  const Eigen::Vector3d v = svd.matrixV().col(2);
  const double sign = v[2] < 0 ? -1.0 : 1.0;
  theta[1] = std::atan2(sign * v[1], sign * v[0]);
  const Pose<double> M = K[0] * rot_z(theta[1]) * G;
  const Eigen::Vector3d u = M.p, w = M.R.col(2);
  const double cross = u.x() * t.y() - u.y() * t.x() + w.x() * l.y() - w.y() * l.x();
  const double dot = u.x() * t.x() + u.y() * t.y() + w.x() * l.x() + w.y() * l.y();
  theta[0] = std::atan2(cross, dot);
  const Eigen::Matrix3d R6 = (rot_z(theta[0]) * M).R.transpose() * Tp.R;
  theta[5] = std::atan2(R6(1, 0), R6(0, 0));
}

/// A fixed mixing of k ≥ 6 equations into 6 (only when the θ1θ2 coefficients lose rank).
Eigen::MatrixXd mixing(int k) {
  Eigen::MatrixXd m(6, k);
  for (int i = 0; i < 6; ++i)
    for (int j = 0; j < k; ++j) m(i, j) = i == j ? 1.0 : 0.25 * std::sin(1.0 + 7.0 * i + 3.0 * j);
  return m;
}

/// The monomial vectors v = (x4^i·x5^j) in the span of the orthonormal columns N of a null
/// space of M(x3): a shift of the monomials (i → i+1 is a product with x4, j → j+1 with x5) maps
/// N·c to μ·N·c with μ = x4 + κ·x5 on the rows where both shifts exist, a k×k eigenproblem
/// (least squares) whose eigenvectors c give each v, passed to `use`.
template <int K, typename Use>
void null_space_monomials(const Eigen::Matrix<double, 12, K>& N, Use&& use) {
  constexpr double kKappa = 0.6180339887;  // any value that keeps the μ of distinct (x4, x5) apart
  Eigen::Matrix<double, 6, K> from, to;
  int r = 0;
  for (int i = 0; i <= 2; ++i)
    for (int j = 0; j <= 1; ++j, ++r) {
      const int m = 3 * i + j;
      from.row(r) = N.row(m);
      to.row(r) = N.row(m + 3) + kKappa * N.row(m + 1);
    }
  const Eigen::Matrix<double, K, K> shift = from.colPivHouseholderQr().solve(to);
  const Eigen::EigenSolver<Eigen::Matrix<double, K, K>> eigen(shift, true);
  if (eigen.info() != Eigen::Success) return;
  for (int c = 0; c < K; ++c) use(Vector12(N * eigen.eigenvectors().col(c).real()));
}

ArmConfig label(const Frames<double>& f, double theta5) {
  const Eigen::Vector3d x1 = f.frame[0].R.col(0), y1 = f.frame[0].R.col(1);
  const Eigen::Vector3d S = f.frame[1].p, E = f.frame[2].p, W = f.frame[3].p;
  ArmConfig c{};
  c.back = (f.frame[4].p - f.frame[0].p).dot(x1) < 0;
  const double side = (W - S).cross(E - S).dot(-y1);
  c.down = (c.back ? -side : side) <= 0;
  c.flip = std::sin(theta5) < 0;
  return c;
}

}  // namespace

std::optional<General6rGeometry> analyze_general_6r(const RobotModel& model, std::string* why_not) {
  const auto joints = analyze_closed_form_joints(model, why_not);
  if (!joints) return std::nullopt;
  General6rGeometry g;
  static_cast<ClosedFormJoints&>(g) = *joints;
  const ParameterVector p = model.nominal();
  g.base.p = Eigen::Vector3d(0, 0, model.mdh[0].d);
  double length = std::abs(model.mdh[0].d);
  for (int link = 2; link <= kJointCount; ++link) {
    g.link[link - 2] = detail::mdh_transform(p[link_param(link, 0)], p[link_param(link, 1)], 0.0,
                                             p[link_param(link, 3)]);
    length += std::abs(p[link_param(link, 1)]) + std::abs(p[link_param(link, 3)]);
  }
  g.length_scale = std::max(length, 1.0);
  // The elimination degenerates on some special shapes for some choices of the eliminated
  // joint: take the first cyclic shift of the loop on which eight arbitrary configurations
  // are found again (three were not enough: the Stäubli TX2-60 started at joint 5 finds them
  // but misses a third of random configurations).
  const std::array<Angles, 8> probes = {
      Angles{0.3, -0.7, 1.1, 0.5, -1.3, 0.9},  Angles{-2.1, 0.4, -0.6, 2.5, 0.8, -1.7},
      Angles{1.4, 1.9, 2.6, -0.4, 2.2, 0.1},   Angles{-0.9, -1.6, 0.2, -2.8, 1.7, 2.4},
      Angles{2.7, 0.9, -1.9, 1.3, -0.5, -2.6}, Angles{-1.2, 2.3, -2.7, -1.1, -2.4, 1.5},
      Angles{0.8, -2.5, 1.6, 3.0, 0.4, -0.8},  Angles{-2.9, -0.2, 0.7, -1.8, 1.1, 2.9}};
  for (g.cyclic_shift = 0; g.cyclic_shift < kJointCount; ++g.cyclic_shift) {
    // The kept links K3..K5 of this start; without the pose, their part is computed once.
    const auto kept = [&](int i) {
      return scaled(g.link[(i + g.cyclic_shift) % kJointCount], g.length_scale);
    };
    const int pose_link = (2 * kJointCount - 1 - g.cyclic_shift) % kJointCount;
    g.elimination = pose_link < 2 || pose_link > 4
                        ? std::make_shared<const General6rElimination>(
                              kept_joints_elimination(kept(2), kept(3), kept(4)))
                        : nullptr;
    bool all_found = true;
    for (const Angles& probe : probes) {
      std::array<Angles, kMaxGeneral6rSolutions> found;
      const int n = general_6r_link_angles(g, forward(g, probe).flange, found);
      bool again = false;
      for (int k = 0; k < n && !again; ++k) {
        double d = 0;
        for (int i = 0; i < kJointCount; ++i)
          d = std::max(d, std::abs(wrap(found[k][i] - probe[i])));
        again = d < 1e-6;
      }
      all_found = all_found && again;
    }
    if (all_found) return g;
  }
  if (why_not)
    *why_not =
        "the general 6R elimination is degenerate for this geometry with every choice of the "
        "eliminated joint (test poses not found again)";
  return std::nullopt;
}

int general_6r_link_angles(const General6rGeometry& g, const Pose<double>& world_T_flange,
                           std::array<Angles, kMaxGeneral6rSolutions>& out,
                           General6rCounts* counts) {
  const double L = g.length_scale;
  // The loop Rz(θ1)·J1⋯Rz(θ6)·J6 = I with J_i = K_i (i ≤ 5), J6 = T'⁻¹, started at joint
  // 1 + cyclic_shift: φ_i = θ_{i+shift}, K_i in the header's equations becomes J_{i+shift}.
  std::array<Pose<double>, kJointCount> loop;
  for (int i = 0; i < 5; ++i) loop[i] = scaled(g.link[i], L);
  loop[5] = scaled(g.base.inverse() * world_T_flange, L).inverse();
  std::array<Pose<double>, 5> K;
  for (int i = 0; i < 5; ++i) K[i] = loop[(i + g.cyclic_shift) % kJointCount];
  const Pose<double> Tp = loop[(5 + g.cyclic_shift) % kJointCount].inverse();
  std::optional<General6rElimination> per_pose;
  if (!g.elimination) per_pose = kept_joints_elimination(K[2], K[3], K[4]);
  const General6rElimination& kept = g.elimination ? *g.elimination : *per_pose;
  const Eigen::Matrix3d& W = kNodeWeights;
  // Right sides at the 9 node pairs, interpolated over {1, cos, sin} of φ1, φ2.
  Eigen::Matrix<double, 14, 9> values, Q = Eigen::Matrix<double, 14, 9>::Zero();
  const Pose<double> K1inv = K[0].inverse(), K2inv = K[1].inverse();
  for (int k1 = 0; k1 < 3; ++k1)
    for (int k2 = 0; k2 < 3; ++k2)
      values.col(3 * k1 + k2) =
          equations(K2inv * rot_z(-kNodes[k2]) * K1inv * rot_z(-kNodes[k1]) * Tp);
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b)
      for (int k1 = 0; k1 < 3; ++k1)
        for (int k2 = 0; k2 < 3; ++k2)
          Q.col(3 * a + b) += W(a, k1) * W(b, k2) * values.col(3 * k1 + k2);
  // Eliminate the 8 non-constant θ1θ2 terms by the left null space of their coefficients (the
  // last columns of a rank-revealing QR's Q).
  const Eigen::ColPivHouseholderQR<Eigen::Matrix<double, 14, 8>> qr(Q.rightCols<8>());
  int rank = 0;
  while (rank < 8 && std::abs(qr.matrixR()(rank, rank)) > 1e-10 * std::abs(qr.matrixR()(0, 0)))
    ++rank;
  const int k = 14 - rank;
  const Eigen::Matrix<double, 14, 14> basis = qr.householderQ();
  Eigen::Matrix<double, 6, 14> project;
  if (k == 6)
    project = basis.rightCols<6>().transpose();
  else
    project = mixing(k) * basis.rightCols(k).transpose();
  // Left side minus the right's constant term, whose half-angle form is (1 + x4²)(1 + x5²)·Q0:
  // the monomials x4^i·x5^j with i and j even.
  std::array<Eigen::Matrix<double, 6, 9>, 3> poly;
  for (int a = 0; a < 3; ++a) poly[a] = project * kept.left[a];
  const Eigen::Matrix<double, 6, 1> constant = project * Q.col(0);
  for (const int m : {0, 2, 6, 8}) poly[0].col(m) -= constant;
  // M(x3) = M0 + M1·x3 + M2·x3² for a θ3 shift; returns the reciprocal condition of M2.
  const auto matrix_polynomial = [&](double shift, std::array<Matrix12, 3>& out) {
    const Eigen::Matrix3d H3 = half_angle(shift);
    for (int power = 0; power < 3; ++power) {
      const Eigen::Matrix<double, 6, 9> E =
          H3(power, 0) * poly[0] + H3(power, 1) * poly[1] + H3(power, 2) * poly[2];
      out[power].setZero();
      out[power].block<6, 9>(0, 0) = E;  // monomials x4^i·x5^j at column 3i + j
      out[power].block<6, 9>(6, 3) = E;  // the same times x4
    }
    return out[2].partialPivLu().rcond();
  };
  // The eigenvalues x3 of the companion matrix C = [0, I; −M2⁻¹M0, −M2⁻¹M1] on Y: the spurious
  // span Z is invariant and Y ⟂ Z, so C is block triangular in [Y, Z] and Yᵀ·C·Y holds the
  // other eigenvalues (docs/method/02-frames.md §7). With the
  // first θ3 shift whose M2 is well conditioned (else the best conditioned); when the real Schur
  // does not converge, with the next such shift.
  std::array<Matrix12, 3> M;
  double phi3 = 0;
  CompanionSpectrum spectrum;
  CompanionBasis lower;
  for (unsigned tried = 0; spectrum.count == 0;) {
    int pick = -1;
    double best_rcond = 1e-15;
    for (int s = 0; s < 4; ++s) {
      if (tried & (1u << s)) continue;
      std::array<Matrix12, 3> trial;
      const double rcond = matrix_polynomial(kShifts3[s], trial);
      if (rcond > best_rcond) {
        best_rcond = rcond;
        pick = s;
        M = trial;
      }
      if (rcond > kWellConditioned) break;
    }
    if (pick < 0) {
      if (counts) *counts = {};
      return 0;
    }
    tried |= 1u << pick;
    phi3 = kShifts3[pick];
    const Eigen::PartialPivLU<Matrix12> lead(M[2]);
    lower = lead.solve(M[0] * kept.top + M[1] * kept.bottom);
    const Companion companion = kept.top_t_bottom - kept.bottom.transpose() * lower;
    companion_eigenvalues(companion, spectrum);
  }
  // (C² + I)·Y's top half: maps an eigenvector w of Yᵀ·C·Y to C's null vector v (below).
  const CompanionBasis eigenvector_map = kept.top - lower;
  int count = 0;
  General6rCounts tally;
  // One candidate (x3, v): θ4, θ5 from v's monomial ratios, θ1, θ2, θ6 from the pose, polished.
  // Returns the solution reached (new or already found), or -1.
  auto candidate = [&](double x3, const Vector12& v) -> int {
    if (count == kMaxGeneral6rSolutions) return -1;
    int m4 = 0, m5 = 0;
    for (int m = 0; m < 9; ++m)  // x4 from v[m + 3]/v[m], i ≤ 2
      if (std::abs(v[m]) > std::abs(v[m4])) m4 = m;
    for (int m = 0; m < 12; ++m)  // x5 from v[m + 1]/v[m], j ≤ 1
      if (m % 3 != 2 && std::abs(v[m]) > std::abs(v[m5])) m5 = m;
    Angles phi{};
    phi[2] = phi3 + 2.0 * std::atan(x3);
    phi[3] = kShift4 + 2.0 * std::atan(v[m4 + 3] / v[m4]);
    phi[4] = kShift5 + 2.0 * std::atan(v[m5 + 1] / v[m5]);
    solve_first_and_last(K, Tp, phi);
    Angles theta;
    for (int i = 0; i < kJointCount; ++i) theta[(i + g.cyclic_shift) % kJointCount] = phi[i];
    // The solution found within `radius` of theta, else -1.
    const auto known = [&](double radius) {
      for (int s = 0; s < count; ++s) {
        double d = 0;
        for (int i = 0; i < kJointCount && d < radius; ++i)
          d = std::max(d, std::abs(wrap(out[s][i] - theta[i])));
        if (d < radius) return s;
      }
      return -1;
    };
    if (const int s = known(kSameStartRad); s >= 0) return s;
    ++tally.polishes;
    if (!polish(g, world_T_flange, theta)) return -1;
    for (double& t : theta) t = wrap(t);
    if (const int s = known(kSameSolutionRad); s >= 0) return s;
    out[count] = theta;
    return count++;
  };
  // Solutions reached from the current cluster (bit s: out[s]), and those whose twins were sought.
  unsigned reached = 0, twins_sought = 0;
  // Candidates from the null space of M(x3), at least `dimension` wide (more when the pivoted QR
  // of M(x3)ᵀ shows it; its last columns of Q are orthogonal to M's rows); returns the width.
  auto null_space_candidates = [&](double x3, int dimension) {
    ++tally.null_spaces;
    const Matrix12 A = M[0] + x3 * (M[1] + x3 * M[2]);
    const Eigen::ColPivHouseholderQR<Matrix12> qr(A.transpose());
    const Vector12 r = qr.matrixR().diagonal().cwiseAbs();
    while (dimension < kMaxCluster && r[11 - dimension] <= kNullSpace * r[0]) ++dimension;
    dimension = std::min(dimension, kMaxCluster);
    // The last kMaxCluster columns of Q only.
    Eigen::Matrix<double, 12, kMaxCluster> Q = Eigen::Matrix<double, 12, kMaxCluster>::Zero();
    Q.bottomRows<kMaxCluster>().setIdentity();
    Q.applyOnTheLeft(qr.householderQ());
    const auto use = [&](const Vector12& v) {
      if (const int s = candidate(x3, v); s >= 0) reached |= 1u << s;
    };
    if (dimension == 1) use(Q.col(kMaxCluster - 1));
    if (dimension == 2) null_space_monomials<2>(Q.rightCols<2>(), use);
    if (dimension == 3) null_space_monomials<3>(Q.rightCols<3>(), use);
    if (dimension == 4) null_space_monomials<4>(Q.rightCols<4>(), use);
    return dimension;
  };
  // Real candidates (both members of a near-real conjugate pair), by real part.
  std::array<int, 24> order{};
  int n = 0;
  const std::array<std::complex<double>, 24>& eigenvalues = spectrum.eigenvalues;
  const int eigenvalue_count = spectrum.count;
  for (int e = 0; e < eigenvalue_count; ++e) {
    const std::complex<double> lambda = eigenvalues[e];
    if (std::abs(lambda.imag()) <= kRealEigenvalue * (1 + std::abs(lambda))) order[n++] = e;
  }
  const auto x3_of = [&](int e) { return eigenvalues[e].real(); };
  std::sort(order.begin(), order.begin() + n, [&](int a, int b) { return x3_of(a) < x3_of(b); });
  tally.real_roots = n;
  for (int b = 0, e = 0; b < n; b = e) {
    reached = 0;
    // A cluster: roots within kSameRoot of each other (two solutions sharing, or nearly
    // sharing, the eliminated angle: a double root split by rounding, or a conjugate pair).
    for (e = b + 1; e < n && x3_of(order[e]) - x3_of(order[e - 1]) <=
                                 kSameRoot * (1 + std::abs(x3_of(order[e])));
         ++e) {
    }
    // Each root's own null vector (a conjugate pair's at their common real part), then, for a
    // cluster, the null space at its mean: the eigenvectors of a multiple root are any mix of
    // its solutions' vectors, and rounding moves the split roots off each solution's own x3.
    // A null space as wide as the cluster found at one root holds all of them.
    double x3 = 0;
    int found = 0;
    for (int k = b; k < e; ++k) {
      const std::complex<double> lambda = eigenvalues[order[k]];
      x3 += lambda.real() / (e - b);
      if (e - b == 1 && lambda.imag() == 0) {
        // A lone real root: the null vector from the eigenvector w of Yᵀ·C·Y (docs/method/
        // 02-frames.md §7). Y·w is C's eigenvector [v; x3·v] plus a part s in the spurious span,
        // where C² = −I: (C² + I)·Y·w ∝ [v; x3·v], v ∝ (top − M2⁻¹(M0·top + M1·bottom))·w.
        // When it gives no new solution, the pivoted QR's null space as before (wider where it
        // shows more: near-singular poses, where a root's eigenvector is poorly determined).
        const Vector12 v = eigenvector_map * companion_eigenvector(spectrum, lambda.real());
        const int before = count;
        if (const int s = candidate(lambda.real(), v); s >= 0) reached |= 1u << s;
        tally.eigenvector_solutions += count > before;
        found = count > before ? 1 : null_space_candidates(lambda.real(), 1);
      } else if (lambda.imag() >= 0 && found < e - b) {
        found = std::max(found, null_space_candidates(lambda.real(), 1));
      }
    }
    if (found < e - b) null_space_candidates(x3, e - b);
    // Fewer solutions at this x3 than roots from a multiple cluster, or from a crowded lone root
    // whose solutions are off its eigenvalue by more than rounding: a twin may share a solution's
    // exact x3 (a multiple root split beyond the cluster, or both candidates of a double root
    // polished to one twin); M(x3) there has it in its near-null space, three wide (on the CRX
    // two structural directions have singular values ~1e-6 at every x3, and the twin's vector
    // mixes with them). Solutions reached from here but lying at another root's x3 do not count.
    bool crowded = false;
    for (int k = b; k < e && !crowded; ++k)
      for (int o = 0; o < eigenvalue_count && !crowded; ++o) {
        const std::complex<double> lambda = eigenvalues[order[k]];
        const bool inside = std::find(order.begin() + b, order.begin() + e, o) != order.begin() + e;
        crowded = !inside && std::abs(eigenvalues[o] - lambda) <= kCrowded * (1 + std::abs(lambda));
      }
    const auto x3_of_solution = [&](int s) {
      return std::tan(wrap(out[s][(2 + g.cyclic_shift) % kJointCount] - phi3) / 2);
    };
    int reached_here = 0;
    bool rounding_only = true;
    for (int s = 0; s < count; ++s) {
      if (!(reached >> s & 1u)) continue;
      const double offset = std::abs(x3_of_solution(s) - x3);
      reached_here += offset <= kCrowded * (1 + std::abs(x3));
      rounding_only = rounding_only && offset <= kSimpleRoot * (1 + std::abs(x3));
    }
    if ((e - b > 1 || (crowded && !rounding_only)) && reached_here < std::max(2, e - b)) {
      const unsigned seek = reached & ~twins_sought;
      twins_sought |= seek;
      for (int s = 0; s < count; ++s)
        if (seek & (1u << s)) {
          ++tally.twin_searches;
          null_space_candidates(x3_of_solution(s), 3);
        }
    }
  }
  if (counts) *counts = tally;
  return count;
}

IkResult nominal_ik(const General6rGeometry& geometry, const Pose<double>& world_T_flange,
                    const Vector6d& seed, unsigned branch_mask) {
  std::array<Angles, kMaxGeneral6rSolutions> theta;
  const int n = general_6r_link_angles(geometry, world_T_flange, theta);
  IkResult result;
  IkSink sink(geometry, seed, result.solutions.data(), kMaxIkSolutions, false);
  for (int k = 0; k < n; ++k) {
    const ArmConfig config = label(forward(geometry, theta[k]), theta[k][4]);
    if (branch_mask & (1u << config.index())) sink.add(theta[k], config, false, false);
  }
  sink.finish(result);
  return result;
}

IkBranchResult nominal_ik_branch(const General6rGeometry& geometry,
                                 const Pose<double>& world_T_flange, const ArmConfig& config,
                                 const Vector6d& seed) {
  const IkResult all = nominal_ik(geometry, world_T_flange, seed, 1u << config.index());
  IkBranchResult result;
  result.status = all.status == IkStatus::Truncated ? IkStatus::Solved : all.status;
  if (const IkSolution* nearest = nearest_solution(all, seed)) result.solution = *nearest;
  return result;
}

}  // namespace robcal
