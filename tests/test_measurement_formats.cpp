// Measurement files as instruments and controllers write them: Euler columns of the robot
// makers and of tracker software (all 12 rotation orders), declared units, the refusal of
// undeclared units that look wrong, a UTF-8 byte-order mark, and the messages of every new
// form of bad input (file, line, column).

#include <gtest/gtest.h>

#include <fmt/format.h>

#include <Eigen/Geometry>
#include <cmath>

#include "robcal/core/error.hpp"
#include "robcal/core/units.hpp"
#include "robcal/io/measurement_file.hpp"

namespace robcal {
namespace {

Tool one_target_tool() {
  Tool tool;
  tool.targets = {{"A", {0, 0, 125}, true}};
  return tool;
}

MeasurementFile parse(const std::string& text, const MeasurementFormat& format = {}) {
  return parse_measurements_csv(text, "m.csv", one_target_tool(), {}, format);
}

std::string error_of(const std::string& text, const MeasurementFormat& format = {}) {
  try {
    (void)parse(text, format);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

Eigen::Matrix3d axis_rotation(int axis, double deg) {
  return Eigen::AngleAxisd(deg2rad(deg), Eigen::Vector3d::Unit(axis)).toRotationMatrix();
}

/// Independent composition: extrinsic rotations act about the fixed axes, each new one applied
/// on the left; intrinsic ones about the moving axes, each new one on the right.
Eigen::Matrix3d compose(const std::array<int, 3>& axes, bool intrinsic,
                        const Eigen::Vector3d& deg) {
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
  for (int axis : axes) {
    const Eigen::Matrix3d step = axis_rotation(axis, deg[axis]);
    R = intrinsic ? Eigen::Matrix3d(R * step) : Eigen::Matrix3d(step * R);
  }
  return R;
}

const char* kJoints = "10,20,30,40,50,60";

TEST(MeasurementFormats, AllTwelveRotationOrdersOfRxRyRz) {
  const Eigen::Vector3d deg(12.5, -33, 71);  // about x, y, z
  const std::array<std::array<int, 3>, 6> orders = {
      {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}}};
  int distinct = 0;
  std::vector<Eigen::Matrix3d> seen;
  for (const auto& axes : orders)
    for (bool intrinsic : {true, false}) {
      std::string name = intrinsic ? "intrinsic " : "extrinsic ";
      for (int a : axes) name += static_cast<char>('X' + a);
      const std::string text = "# euler: " + name + "\nconfig,j1,j2,j3,j4,j5,j6,x,y,z,rx,ry,rz\n" +
                               "p1," + kJoints + ",400,0,500,12.5,-33,71\n";
      const MeasurementFile file = parse(text);
      ASSERT_EQ(file.measurements.kind, MeasurementKind::Poses) << name;
      const Eigen::Matrix3d expected = compose(axes, intrinsic, deg);
      EXPECT_LT((file.measurements.poses[0].world_T_tcp.R - expected).norm(), 1e-12) << name;
      bool is_new = true;
      for (const auto& R : seen) is_new = is_new && (R - expected).norm() > 1e-6;
      distinct += is_new;
      seen.push_back(expected);
    }
  // Intrinsic ABC equals extrinsic CBA: 12 names, 6 distinct matrices.
  EXPECT_EQ(distinct, 6);
}

TEST(MeasurementFormats, MakersEulerColumnsGiveTheSameRotationAsTheQuaternion) {
  // ABB/KUKA A, B, C = 30, -20, 110 (deg): R = Rz(30)·Ry(−20)·Rx(110).
  const Eigen::Matrix3d R = axis_rotation(2, 30) * axis_rotation(1, -20) * axis_rotation(0, 110);
  const Eigen::Quaterniond q(R);
  const std::string quat = fmt::format(
      "config,j1,j2,j3,j4,j5,j6,x,y,z,qw,qx,qy,qz\np1,{},1,2,3,"
      "{:.12f},{:.12f},{:.12f},{:.12f}\n",
      kJoints, q.w(), q.x(), q.y(), q.z());
  const std::string abc =
      std::string("config,j1,j2,j3,j4,j5,j6,x,y,z,a,b,c\np1,") + kJoints + ",1,2,3,30,-20,110\n";
  const std::string wpr =
      std::string("config,j1,j2,j3,j4,j5,j6,x,y,z,w,p,r\np1,") + kJoints + ",1,2,3,110,-20,30\n";
  const std::string rxyz =
      std::string("config,j1,j2,j3,j4,j5,j6,x,y,z,rz,ry,rx\np1,") + kJoints + ",1,2,3,30,-20,110\n";
  MeasurementFormat extrinsic_xyz;
  extrinsic_xyz.euler = parse_euler_order("extrinsic XYZ", {});
  for (const auto& [text, format] : std::vector<std::pair<std::string, MeasurementFormat>>{
           {quat, {}}, {abc, {}}, {wpr, {}}, {rxyz, extrinsic_xyz}}) {
    const MeasurementFile file = parse(text, format);
    ASSERT_EQ(file.measurements.poses.size(), 1u);
    EXPECT_LT((file.measurements.poses[0].world_T_tcp.R - R).norm(), 1e-9) << text;
    EXPECT_TRUE(file.warnings.empty()) << text;
  }
}

TEST(MeasurementFormats, DeclaredUnitsByHeaderOrOption) {
  const std::string rows = "p1,0.1,0.2,0.3,0.4,0.5,0.6,0.4,-0.05,0.5,0.1,0.2,-0.3\n";
  const std::string header = "config,j1,j2,j3,j4,j5,j6,x,y,z,a,b,c\n";
  MeasurementFormat metres_radians;
  parse_units("m, rad", {}, metres_radians);
  for (const MeasurementFile& file :
       {parse("# units: m, rad\n" + header + rows), parse(header + rows, metres_radians),
        parse("# Units: RAD m\n" + header + rows)}) {
    const PoseMeasurement& m = file.measurements.poses[0];
    EXPECT_NEAR(m.joints[2], 0.3, 1e-15);
    EXPECT_LT((m.world_T_tcp.p - Eigen::Vector3d(400, -50, 500)).norm(), 1e-12);
    const Eigen::Matrix3d R = Eigen::AngleAxisd(0.1, Eigen::Vector3d::UnitZ()) *
                              Eigen::AngleAxisd(0.2, Eigen::Vector3d::UnitY()) *
                              Eigen::AngleAxisd(-0.3, Eigen::Vector3d::UnitX()).toRotationMatrix();
    EXPECT_LT((m.world_T_tcp.R - R).norm(), 1e-12);
  }
  // Distances in metres.
  const MeasurementFile d =
      parse("# units: m\nconfig,target,j1,j2,j3,j4,j5,j6,length\nc1,A,0,10,20,30,40,50,0.15\n");
  EXPECT_DOUBLE_EQ(d.measurements.distances[0].length_mm, 150.0);
  EXPECT_DOUBLE_EQ(d.measurements.distances[0].joints[1], deg2rad(10.0));
}

TEST(MeasurementFormats, ByteOrderMarkIsSkipped) {
  const MeasurementFile file = parse(
      "\xEF\xBB\xBF"
      "config,target,j1,j2,j3,j4,j5,j6,x,y,z\nc1,A,0,0,0,0,0,0,1,2,3\n");
  ASSERT_EQ(file.measurements.points.size(), 1u);
  EXPECT_TRUE(file.warnings.empty());
}

/// Five rows of a points file, positions and joints as given.
std::string five_points(double scale, double joint) {
  std::string text = "config,target,j1,j2,j3,j4,j5,j6,x,y,z\n";
  for (int k = 0; k < 5; ++k)
    text += fmt::format("c{},A,{},{},0,0,{},0,{},{},{}\n", k, joint * k / 4, -joint / 2, joint,
                        scale * (0.3 + 0.1 * k), scale * 0.2 * k, scale * 0.5);
  return text;
}

TEST(MeasurementFormats, UndeclaredUnitsThatLookWrongAreRefused) {
  EXPECT_EQ(error_of(five_points(1, 80)),
            "m.csv:1:9 (x): the positions span only 0.8 mm over 5 rows: they look like metres, "
            "not millimetres; declare the units with a header comment such as '# units: m, deg' "
            "(or the --units option); '# units: mm, deg' if they really are");
  EXPECT_EQ(error_of(five_points(1000, 1.2)),
            "m.csv:1:3 (j1): every joint value is within ±1.200 over 5 rows: they look like "
            "radians, not degrees; declare the units with a header comment such as "
            "'# units: mm, rad' (or the --units option); '# units: mm, deg' if they really are "
            "degrees");
  // Declared, they are read as declared.
  EXPECT_EQ(error_of("# units: m\n" + five_points(1, 80)), "");
  EXPECT_EQ(error_of("# units: mm, deg\n" + five_points(1, 80)), "");
  EXPECT_EQ(error_of("# units: rad\n" + five_points(1000, 1.2)), "");
  EXPECT_EQ(error_of(five_points(1000, 80)), "");
  EXPECT_NE(error_of("config,target,j1,j2,j3,j4,j5,j6,length\n"
                     "c1,A,0,10,20,30,40,50,0.15\nc2,A,0,10,20,30,40,51,0.15\n"
                     "c3,A,0,10,20,30,40,52,0.15\nc4,A,0,10,20,30,40,53,0.15\n"
                     "c5,A,0,10,20,30,40,54,0.15\n")
                .find("m.csv:1:9 (length): the lengths reach only 0.15 mm over 5 rows"),
            std::string::npos);
}

TEST(MeasurementFormats, BadDeclarationsAndOrientationColumnsNameThePlace) {
  const std::string pose_header = "config,j1,j2,j3,j4,j5,j6,x,y,z,";
  const std::string row = std::string("p1,") + kJoints + ",1,2,3,4,5,6\n";
  EXPECT_EQ(error_of(pose_header + "rx,ry,rz\n" + row),
            "m.csv:1:11 (rx): columns rx,ry,rz need their rotation order declared: add a header "
            "comment such as '# euler: intrinsic ZYX' (or extrinsic; any order of X, Y, Z) or "
            "give --euler");
  EXPECT_EQ(error_of(pose_header + "roll,pitch,yaw\n" + row),
            "m.csv:1:12 (pitch): unsupported orientation columns: found pitch,roll,yaw; "
            "accepted: qw,qx,qy,qz (unit quaternion), a,b,c (ABB/KUKA, Rz(a)·Ry(b)·Rx(c)), w,p,r "
            "(Fanuc, Rz(r)·Ry(p)·Rx(w)) or rx,ry,rz with a declared order ('# euler: intrinsic "
            "ZYX'), exactly one set");
  EXPECT_NE(error_of(pose_header + "a,b\n" + std::string("p1,") + kJoints + ",1,2,3,4,5\n")
                .find("m.csv:1:11 (a): unsupported orientation columns: found a,b; accepted:"),
            std::string::npos);
  EXPECT_NE(error_of("# euler: intrinsic ZYX\n" + pose_header + "a,b,c,rx,ry,rz\n" +
                     std::string("p1,") + kJoints + ",1,2,3,4,5,6,7,8,9\n")
                .find("m.csv:2:11 (a): more than one set of orientation columns: found "
                      "a,b,c,rx,ry,rz"),
            std::string::npos);
  EXPECT_EQ(error_of("# units: inch, deg\n" + pose_header + "a,b,c\n" + row),
            "m.csv:1: unknown unit 'inch': expected a length unit (mm or m) and/or an angle unit "
            "(deg or rad), e.g. 'm, rad'");
  EXPECT_EQ(error_of("# units:\n" + pose_header + "a,b,c\n" + row),
            "m.csv:1: no unit given: expected a length unit (mm or m) and/or an angle unit (deg "
            "or rad), e.g. 'm, rad'");
  EXPECT_EQ(error_of("#\n# euler: ZYX\n" + pose_header + "rx,ry,rz\n" + row),
            "m.csv:2: 'zyx' is not a rotation order: expected 'intrinsic' or 'extrinsic' and the "
            "three axes X, Y, Z in the order of the rotations, e.g. 'intrinsic ZYX'");
  EXPECT_NE(error_of("# euler: intrinsic ZZX\n" + pose_header + "rx,ry,rz\n" + row)
                .find("m.csv:1: 'intrinsic zzx' is not a rotation order"),
            std::string::npos);
  MeasurementFormat mm;
  parse_units("mm", {"", 0, 0, "--units"}, mm);
  EXPECT_EQ(error_of("# units: m\n" + pose_header + "a,b,c\n" + row, mm),
            "m.csv:1: the file declares a length unit other than the command line's option: "
            "remove one of them");
  try {
    parse_units("feet", {"", 0, 0, "--units"}, mm);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()).substr(0, 25), "--units: unknown unit 'fe");
  }
  // An angle column in a points file (it has `target`) is ignored with the usual warning.
  const MeasurementFile points =
      parse("config,target,j1,j2,j3,j4,j5,j6,x,y,z,a\nc1,A,0,0,0,0,0,0,1,2,3,9\n");
  ASSERT_EQ(points.warnings.size(), 1u);
  EXPECT_EQ(points.warnings[0], "m.csv:1:12: column 'a' is not used by a points file; ignored");
}

}  // namespace
}  // namespace robcal
