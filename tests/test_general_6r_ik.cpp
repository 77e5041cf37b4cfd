// The general 6R inverse (general_6r_ik.hpp) on random geometries, the Fanuc CRX and the robots
// with closed forms: every returned solution reproduces the pose, the generating joints are
// found, and a dense multi-start numeric search finds no solution the solver missed.

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <iterator>
#include <limits>

#include <numbers>
#include <random>

#include "robcal/io/robot_file.hpp"
#include "robcal/kinematics/closed_form_ik.hpp"
#include "robcal/kinematics/general_6r_ik.hpp"
#include "robcal/kinematics/nominal_chain.hpp"
#include "robcal/kinematics/numeric_ik.hpp"
#include "test_support.hpp"

namespace robcal {
namespace {

constexpr double kPi = std::numbers::pi;

/// A random 6R arm: twists anywhere, lengths and offsets within ±400 mm, joints ±180°.
RobotModel random_6r(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> twist(-kPi, kPi), length(-400.0, 400.0);
  RobotModel m;
  m.name = "random 6R";
  m.mdh[0] = {0.0, 0.0, twist(rng), length(rng)};
  for (int i = 1; i < kJointCount; ++i)
    m.mdh[i] = {twist(rng), length(rng), twist(rng), length(rng)};
  for (JointLimit& l : m.limits) l = {-kPi, kPi};
  return m;
}

Vector6d uniform_joints(const RobotModel& m, std::mt19937_64& rng) {
  Vector6d q;
  for (int i = 0; i < kJointCount; ++i)
    q[i] = std::uniform_real_distribution<double>(m.limits[i].lower, m.limits[i].upper)(rng);
  return q;
}

double wrapped_distance(const Vector6d& a, const Vector6d& b) {
  double d = 0;
  for (int i = 0; i < kJointCount; ++i)
    d = std::max(d, std::abs(std::remainder(a[i] - b[i], 2 * kPi)));
  return d;
}

struct RoundTrip {
  int poses = 0, missed = 0, inexact = 0;
  double worst_mm = 0, worst_rad = 0;
  std::array<int, kMaxGeneral6rSolutions + 1> histogram{};
};

/// FK of random joints, solved: the joints are among the solutions and each reproduces the pose.
void round_trip(const RobotModel& model, const General6rGeometry& g, int poses,
                std::mt19937_64& rng, RoundTrip& st) {
  const NominalChain chain = make_nominal_chain(model);
  for (int k = 0; k < poses; ++k) {
    const Vector6d q = uniform_joints(model, rng);
    const Pose<double> target = nominal_flange_pose(chain, q);
    const IkResult r = nominal_ik(g, target, q);
    ++st.poses;
    ++st.histogram[std::min(r.count, kMaxGeneral6rSolutions)];
    bool found = false;
    for (const IkSolution& s : r) {
      const Pose<double> back = nominal_flange_pose(chain, s.joints);
      const double mm = (back.p - target.p).norm();
      const double rad = Eigen::AngleAxisd(Eigen::Matrix3d(back.R * target.R.transpose())).angle();
      st.worst_mm = std::max(st.worst_mm, mm);
      st.worst_rad = std::max(st.worst_rad, rad);
      st.inexact += mm > 1e-9 || rad > 1e-11;
      found = found || wrapped_distance(s.joints, q) < 1e-9;
      EXPECT_EQ(s.config, arm_config(model, s.joints));
    }
    st.missed += !found;
  }
}

// 100 random geometries × 40 poses: the generating joints always found, every solution exact.
TEST(General6rIk, RandomGeometriesRoundTrip) {
  auto rng = test::seeded_rng(1502);
  RoundTrip st;
  int refused = 0;
  for (int robot = 0; robot < 100; ++robot) {
    const RobotModel model = random_6r(rng);
    std::string why;
    const auto g = analyze_general_6r(model, &why);
    if (!g) {
      ++refused;
      continue;
    }
    round_trip(model, *g, 40, rng, st);
  }
  std::string hist;
  int odd = 0;
  for (int n = 0; n <= kMaxGeneral6rSolutions; ++n) {
    if (n % 2) odd += st.histogram[n];
    if (st.histogram[n]) hist += fmt::format(" {}:{}", n, st.histogram[n]);
  }
  std::printf("[random 6R] %d poses, %d missed, %d inexact, worst %.2e mm %.2e rad; solutions%s\n",
              st.poses, st.missed, st.inexact, st.worst_mm, st.worst_rad, hist.c_str());
  EXPECT_EQ(refused, 0);
  EXPECT_EQ(st.missed, 0);
  EXPECT_EQ(st.inexact, 0);
  // Real roots of a real polynomial of degree 16 come in even numbers away from double roots:
  // an odd count would be a missed (or invented) solution.
  EXPECT_EQ(odd, 0);
}

// Which paths the solver takes (General6rCounts): a lone real root's companion eigenvector gives
// its solution without a pivoted-QR null space (an eigenvector that only polishes to solutions
// already found falls back to the QR and passes every round trip, only slower), and on the CRX
// the twin search runs only where a root's solutions are off its eigenvalue by more than
// rounding. Searching every crowded root (kSimpleRoot = 0) gives 2986 twin searches here and
// fails all four bounds.
TEST(General6rIk, LoneRootsTakeTheirEigenvectorAndTwinsAreSoughtOnlyOffRounding) {
  auto rng = test::seeded_rng(1507);
  const auto tally = [&](const RobotModel& model, const General6rGeometry& g, int poses,
                         General6rCounts& sum) {
    const NominalChain chain = make_nominal_chain(model);
    for (int k = 0; k < poses; ++k) {
      std::array<std::array<double, kJointCount>, kMaxGeneral6rSolutions> out;
      General6rCounts c;
      general_6r_link_angles(g, nominal_flange_pose(chain, uniform_joints(model, rng)), out, &c);
      sum += c;
    }
  };
  General6rCounts random;
  for (int robot = 0; robot < 20; ++robot) {
    const RobotModel model = random_6r(rng);
    const auto g = analyze_general_6r(model);
    ASSERT_TRUE(g);
    tally(model, *g, 40, random);
  }
  const RobotModel crx_model = load_robot("fanuc-crx10ia-l");
  const auto crx_geometry = analyze_general_6r(crx_model);
  ASSERT_TRUE(crx_geometry);
  General6rCounts crx;
  tally(crx_model, *crx_geometry, 500, crx);
  std::printf(
      "[random 6R, 800 poses] real roots %d, eigenvector solutions %d, null spaces %d, "
      "twin searches %d, polishes %d\n[CRX-10iA/L, 500 poses] real roots %d, eigenvector "
      "solutions %d, null spaces %d, twin searches %d, polishes %d\n",
      random.real_roots, random.eigenvector_solutions, random.null_spaces, random.twin_searches,
      random.polishes, crx.real_roots, crx.eigenvector_solutions, crx.null_spaces,
      crx.twin_searches, crx.polishes);
  EXPECT_GE(random.eigenvector_solutions, 0.97 * random.real_roots);
  EXPECT_LE(random.null_spaces, 0.03 * random.real_roots);
  EXPECT_GE(crx.eigenvector_solutions, 0.85 * crx.real_roots);
  EXPECT_LE(crx.twin_searches, 500);
}

/// Solutions a damped-least-squares search from `starts` random seeds converges to, which the
/// solver did not return (identity joint map: controller joints are link angles minus offsets).
int missed_by_solver(const RobotModel& model, const IkResult& r, const Pose<double>& target,
                     int starts, std::mt19937_64& rng, int& numeric_found) {
  int missed = 0;
  std::vector<Vector6d> seen;
  NumericIkOptions options;
  options.position_tolerance_mm = 1e-9;
  options.orientation_tolerance_rad = 1e-12;
  for (int s = 0; s < starts; ++s) {
    Vector6d seed;
    for (double& x : seed) x = std::uniform_real_distribution<double>(-kPi, kPi)(rng);
    const NumericIkResult n =
        numeric_ik(model, PointMass{}, model.nominal(), target, seed, options);
    if (n.status != NumericIkStatus::Converged) continue;
    bool known = false;
    for (const Vector6d& v : seen) known = known || wrapped_distance(v, n.joints) < 1e-6;
    if (known) continue;
    seen.push_back(n.joints);
    bool returned = false;
    for (const IkSolution& sol : r)
      returned = returned || wrapped_distance(sol.joints, n.joints) < 1e-6;
    missed += !returned;
  }
  numeric_found += static_cast<int>(seen.size());
  return missed;
}

struct SearchCount {
  int returned = 0, numeric = 0, missed = 0;
};

/// missed_by_solver on `poses` random poses of `model`.
void search_poses(const RobotModel& model, const General6rGeometry& g, int poses,
                  std::mt19937_64& rng, SearchCount& n) {
  const NominalChain chain = make_nominal_chain(model);
  for (int k = 0; k < poses; ++k) {
    const Pose<double> target = nominal_flange_pose(chain, uniform_joints(model, rng));
    const IkResult r = nominal_ik(g, target);
    n.returned += r.count;
    n.missed += missed_by_solver(model, r, target, 200, rng, n.numeric);
  }
}

void expect_nothing_missed(const char* what, const SearchCount& n) {
  std::printf("[%s] solver %d solutions, multi-start search %d, missed %d\n", what, n.returned,
              n.numeric, n.missed);
  EXPECT_EQ(n.missed, 0) << what;
  EXPECT_GE(n.returned, n.numeric) << what;
}

/// The multi-start search on `poses` poses of each of `arms` random geometries.
SearchCount search_random_arms(uint64_t seed, int arms, int poses) {
  auto rng = test::seeded_rng(seed);
  SearchCount n;
  for (int robot = 0; robot < arms; ++robot) {
    const RobotModel model = random_6r(rng);
    const auto g = analyze_general_6r(model);
    EXPECT_TRUE(g);
    if (g) search_poses(model, *g, poses, rng, n);
  }
  return n;
}

// Exhaustive numeric search: 200 random starts per pose on 8 random geometries × 4 poses find
// nothing the solver missed (and, over all poses, as many distinct solutions as it returns).
TEST(General6rIk, MultiStartNumericSearchFindsNothingMore) {
  expect_nothing_missed("random 6R, 32 poses", search_random_arms(1503, 8, 4));
}

// The full check (10,000 poses: 100 random geometries × 100 poses, 200 starts each);
// minutes, so disabled: run with --gtest_also_run_disabled_tests
// --gtest_filter=General6rIk.DISABLED_MultiStartNumericSearch10000Poses. Session 10: the solver
// returned 34,424 solutions, the search found 34,424, none missed (462 s on a loaded machine).
TEST(General6rIk, DISABLED_MultiStartNumericSearch10000Poses) {
  expect_nothing_missed("random 6R, 10,000 poses", search_random_arms(1507, 100, 100));
}

// The Fanuc CRX-10iA/L (offset wrist, up to 16 solutions): round trip with limits and turns,
// and the multi-start search on 10 poses.
TEST(General6rIk, FanucCrxEverySolution) {
  const RobotModel model = load_robot("fanuc-crx10ia-l");
  std::string why;
  const auto closed = analyze_closed_form(model, &why);
  ASSERT_TRUE(closed) << why;
  ASSERT_TRUE(std::holds_alternative<General6rGeometry>(*closed));
  const General6rGeometry& g = std::get<General6rGeometry>(*closed);
  auto rng = test::seeded_rng(1504);
  RoundTrip st;
  round_trip(model, g, 1500, rng, st);
  std::string hist;
  for (int n = 0; n <= kMaxGeneral6rSolutions; ++n)
    if (st.histogram[n]) hist += fmt::format(" {}:{}", n, st.histogram[n]);
  std::printf("[CRX-10iA/L] %d poses, %d missed, %d inexact, worst %.2e mm %.2e rad; solutions%s\n",
              st.poses, st.missed, st.inexact, st.worst_mm, st.worst_rad, hist.c_str());
  EXPECT_EQ(st.missed, 0);
  EXPECT_EQ(st.inexact, 0);
  // Multi-start search in link angles: the same robot without joint map and limits.
  RobotModel free = model;
  free.joint_map = JointMap{};
  for (JointLimit& l : free.limits) l = {-kPi, kPi};
  const auto gf = analyze_general_6r(free);
  ASSERT_TRUE(gf);
  SearchCount n;
  search_poses(free, *gf, 10, rng, n);
  expect_nothing_missed("CRX-10iA/L, 10 poses", n);
}

// On the CRX the solutions come in pairs sharing the eliminated angle (θ2 here): a double
// eigenvalue whose computed eigenvectors mix the two. Two configurations that were missed that
// way (CRX-10iA with 540/540 arms; CRX-10iA/L) and 3,000 random ones of each: the generating
// joints are found.
TEST(General6rIk, DoubleEigenvaluesLoseNoSolution) {
  const std::pair<const char*, Vector6d> recorded[] = {
      {"fanuc-crx10ia", (Vector6d() << -0.63712723545255256, 2.4156891035941737, 4.4563659578226087,
                         -1.5829786940188164, 0.0059290001949579008, -1.7725514913627956)
                            .finished()},
      {"fanuc-crx10ia-l",
       (Vector6d() << -1.7113358245262686, 1.2870867488345832, -0.25678727820369396,
        -3.1062055889317302, 1.6025404865801898, 1.411472626024771)
           .finished()},
      // Missed before the search at each solution's exact x3 (a defective multiple root split
      // by rounding into neighbouring clusters; 1 in 60,000 random configurations each).
      {"staubli-tx2-60", (Vector6d() << 0.10952613944868927, 1.9484484159089597, 1.9084600404996457,
                          1.9101407229729883, -0.22448572796963218, -3.0698494512844903)
                             .finished()},
      {"doosan-m1013", (Vector6d() << -5.962426631679496, 1.4409252559143493, -0.81668856023752578,
                        -4.0644839308083061, -3.1153809331026783, -1.6309925114978512)
                           .finished()},
      // Missed before the changes of issue 15 (1 in 100,000 random configurations each): both
      // candidates of a double root polished to the twin, and the real Schur of the 24×24 companion
      // did not converge (no solution at all).
      {"fanuc-crx10ia-l",
       (Vector6d() << 0.30682848554319664, -2.9156274775899802, 0.83359661550960684,
        1.5020851254952814, 3.0667192022729939, -0.14627760898757014)
           .finished()},
      {"fanuc-crx10ia-l",
       (Vector6d() << 2.3170793427922574, 0.87818014656458487, -0.42731254736068713,
        3.2076695391854639, 0.71330093279277795, 1.4790905850674698)
           .finished()},
      // Missed with the 24×24 companion (4 of 12 solutions returned; 1 in 100,000): two twin
      // pairs 1.6e-3 apart in x3, a near-quadruple root split into two conjugate pairs with
      // |Im| = 1e-3. The deflated 16×16 companion returns all 12 (why it splits
      // differently there was not analysed).
      {"fanuc-crx10ia", (Vector6d() << 2.6209881596776947, 1.9106174478842721, 2.4819552836940968,
                         1.8604635967318122, 1.2052415793662528, 0.32711423424827712)
                            .finished()},
      // Found only by the twin search at a lone crowded root whose solutions lie 1e-10 or more off
      // its eigenvalue (a multiple root split by rounding; 1 in 100,000): searching no lone root
      // returns 5 of its 8 solutions, q not among them.
      {"fanuc-crx10ia",
       (Vector6d() << -0.53722356733803922, 0.32438784521081532, 4.0212248446764836,
        1.3491950141010833, -0.38202891696950347, 0.32011128482067575)
           .finished()},
      // Returned 5.4e-7 rad from q (1 in 100,000): twins 1.2e-6 rad apart, the smallest
      // singular value of the joint Jacobian 4.3e-5 mm/rad; Newton in double stops short of the
      // near-double root. Newton in long double puts it 5.7e-10 rad from q (the margin to 1e-9 is
      // thin), where the exact root of this rounded pose is.
      {"fanuc-crx10ia-l",
       (Vector6d() << 1.4290965584708797, -0.78516341088470076, 0.13527304241003879,
        1.2264173227663098, -2.3017083876159767, -2.8863967556720698)
           .finished()}};
  for (const auto& [name, q] : recorded) {
    if (&q == &recorded[std::size(recorded) - 1].second &&
        std::numeric_limits<long double>::digits <= std::numeric_limits<double>::digits)
      continue;  // the near-double case needs the extended refinement
    const RobotModel model = load_robot(name);
    const auto g = analyze_general_6r(model);
    ASSERT_TRUE(g) << name;
    const IkResult r = nominal_ik(*g, nominal_flange_pose(make_nominal_chain(model), q), q);
    bool found = false;
    for (const IkSolution& s : r) found = found || wrapped_distance(s.joints, q) < 1e-9;
    EXPECT_TRUE(found) << name << ": the generating joints are not among " << r.count;
  }
  auto rng = test::seeded_rng(1506);
  for (const char* name : {"fanuc-crx10ia", "fanuc-crx10ia-l"}) {
    const RobotModel model = load_robot(name);
    RoundTrip st;
    round_trip(model, *analyze_general_6r(model), 3000, rng, st);
    std::printf("[%s] %d poses, %d missed, %d inexact\n", name, st.poses, st.missed, st.inexact);
    EXPECT_EQ(st.missed, 0) << name;
    EXPECT_EQ(st.inexact, 0) << name;
  }
}

// On robots with a closed form the general method returns the same solution set. (Not on the
// UR family: with three parallel axes the elimination is degenerate and the general method
// refuses it; those robots always take their closed form.)
TEST(General6rIk, AgreesWithTheClosedForms) {
  auto rng = test::seeded_rng(1505);
  for (const char* name : {"abb-irb120", "kuka-kr16-2", "fanuc-m20ia"}) {
    const RobotModel model = load_robot(name);
    const auto closed = analyze_closed_form(model);
    ASSERT_TRUE(closed) << name;
    std::string why;
    const auto g = analyze_general_6r(model, &why);
    ASSERT_TRUE(g) << name << ": the general method refused it: " << why;
    const NominalChain chain = make_nominal_chain(model);
    int differ = 0, compared = 0;
    for (int k = 0; k < 300; ++k) {
      const Vector6d q = uniform_joints(model, rng);
      const Pose<double> target = nominal_flange_pose(chain, q);
      const IkResult a = nominal_ik(*closed, target, q), b = nominal_ik(*g, target, q);
      // Away from the wrist singularities the closed forms' sets are finite and exact.
      bool singular = false;
      for (const IkSolution& s : a) singular = singular || s.wrist_singular || s.shoulder_singular;
      if (singular) continue;
      ++compared;
      bool same = a.count == b.count;
      for (const IkSolution& s : a) {
        bool found = false;
        for (const IkSolution& t : b)
          found = found || (s.joints - t.joints).cwiseAbs().maxCoeff() < 1e-7;
        same = same && found;
      }
      differ += !same;
    }
    std::printf("[%s] general vs closed form: %d poses compared, %d differ\n", name, compared,
                differ);
    EXPECT_EQ(differ, 0) << name;
  }
}

}  // namespace
}  // namespace robcal
