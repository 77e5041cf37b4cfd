#include "robcal/programs/program_filter.hpp"

#include <fmt/compile.h>
#include <fmt/format.h>
#include <fmt/ranges.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <bit>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <iterator>
#include <numbers>
#include <optional>

#include "program_scan.hpp"
#include "robcal/core/error.hpp"
#include "robcal/core/units.hpp"
#include "robcal/io/atomic_file.hpp"
#include "robcal/kinematics/orientation.hpp"

namespace robcal {
namespace {

using detail::NumberField;
using detail::PointSite;

detail::ProgramScan scan(std::string_view text, ProgramLanguage language, const std::string& file,
                         const ProgramFilterOptions& options) {
  require_program_language(text, language, file);
  switch (language) {
    case ProgramLanguage::Rapid:
      return detail::scan_rapid(text, file, options);
    case ProgramLanguage::Krl:
      return detail::scan_krl(text, file, options);
    case ProgramLanguage::FanucLs:
      return detail::scan_ls(text, file, options);
    case ProgramLanguage::UrScript:
      return detail::scan_urscript(text, file, options);
    case ProgramLanguage::Jbi:
      return detail::scan_jbi(text, file, options);
  }
  throw std::logic_error("program filter: unknown language");
}

/// Collects the replacements of one program and applies them in text order (a point's
/// fields are not in text order: KRL writes `{S 6,T 27,X ...}` as readily as `{X ...}`).
/// Each call returns the value the field will read back as.
class Rewriter {
 public:
  explicit Rewriter(std::string_view text) : text_(text) {}

  /// Replaces a number with `value` printed with `decimals`, unless the printed value equals
  /// the written one (then the original bytes stay). `reference` is the written value as read
  /// (a normalised quaternion differs from its text).
  double number(const NumberField& field, double value, int decimals, double reference) {
    static constexpr double kHalfUnit[] = {0.5,  0.05,  0.005, 5e-4,  5e-5,  5e-6,  5e-7,  5e-8,
                                           5e-9, 5e-10, 5e-11, 5e-12, 5e-13, 5e-14, 5e-15, 5e-16};
    const int d = std::clamp(decimals, 0, static_cast<int>(std::size(kHalfUnit)) - 1);
    if (std::abs(value - reference) < kHalfUnit[d]) return field.value;
    // Fixed notation, `d` decimals (std::to_chars: no allocation, no locale).
    char buffer[64];
    const auto [end, error] =
        std::to_chars(buffer, buffer + sizeof buffer, value, std::chars_format::fixed, d);
    if (error != std::errc()) throw std::logic_error("program filter: number too long to print");
    std::string_view printed(buffer, static_cast<size_t>(end - buffer));
    if (printed.find_first_not_of("-0.") == std::string_view::npos && printed[0] == '-')
      printed.remove_prefix(1);  // -0.0000 prints as 0.0000
    double read_back = 0;
    std::from_chars(printed.data(), printed.data() + printed.size(), read_back);
    edits_.push_back({field.begin, field.end, std::string(printed)});
    return read_back;
  }
  double number(const NumberField& field, double value, int decimals) {
    return number(field, value, decimals, field.value);
  }

  double integer(const NumberField& field, int value) {
    if (value == static_cast<int>(field.value)) return field.value;
    std::string printed;
    if (field.binary_digits > 0) {
      // KRL bit literal: keep its width ('B010' stays three digits).
      for (int bit = std::max(field.binary_digits,
                              static_cast<int>(std::bit_width(static_cast<unsigned>(value)))) -
                     1;
           bit >= 0; --bit)
        printed += (value >> bit) & 1 ? '1' : '0';
      printed = "'B" + printed + "'";
    } else {
      printed = std::to_string(value);
    }
    edits_.push_back({field.begin, field.end, std::move(printed)});
    return value;
  }

  std::string apply() {
    // Usually in text order already (points are scanned in text order): no sort then.
    const auto by_begin = [](const Edit& a, const Edit& b) { return a.begin < b.begin; };
    if (!std::is_sorted(edits_.begin(), edits_.end(), by_begin))
      std::sort(edits_.begin(), edits_.end(), by_begin);
    std::string out;
    out.reserve(text_.size() + edits_.size() * 4);
    size_t at = 0;
    for (const Edit& e : edits_) {
      // Two edits of one byte range would mean the scanner reported a number twice.
      if (e.begin < at) throw std::logic_error("program filter: overlapping edits");
      out.append(text_.substr(at, e.begin - at));
      out.append(e.text);
      at = e.end;
    }
    out.append(text_.substr(at));
    return out;
  }

 private:
  struct Edit {
    size_t begin, end;
    std::string text;
  };
  std::string_view text_;
  std::vector<Edit> edits_;
};

/// Nearest equivalent of an angle (deg) to the angle written before: keeps ±180° wraps stable.
double near_written(double angle_deg, double written_deg) {
  return angle_deg + 360.0 * std::round((written_deg - angle_deg) / 360.0);
}

/// Rewrites one point; returns the values its fields will read back as.
std::vector<double> rewrite(Rewriter& out, const PointSite& site, const CorrectedPoint& corrected,
                            ProgramLanguage language, const ProgramFilterOptions& options) {
  const auto& f = site.fields;
  std::vector<double> expected;
  expected.reserve(f.size());
  for (const NumberField& field : f) expected.push_back(field.value);
  if (site.point.is_joint_target && language == ProgramLanguage::Jbi) {
    // Whole encoder pulses (the pulses of an unchanged joint print as written).
    for (int k = 0; k < kJointCount; ++k)
      expected[k] = out.integer(
          f[k], static_cast<int>(std::lround(corrected.joints_deg[k] *
                                             options.pulses_per_degree[static_cast<size_t>(k)])));
    return expected;
  }
  if (site.point.is_joint_target && language == ProgramLanguage::UrScript) {
    // Radians, printed to the resolution of the Cartesian rotation vectors.
    for (int k = 0; k < kJointCount; ++k)
      expected[k] = out.number(f[k], deg2rad(corrected.joints_deg[k]), options.angle_decimals + 3);
    return expected;
  }
  if (site.point.is_joint_target) {
    for (int k = 0; k < kJointCount; ++k)
      expected[k] = out.number(f[k], corrected.joints_deg[k], options.angle_decimals);
    return expected;
  }
  if (language == ProgramLanguage::UrScript) {
    // Metres and a rotation vector (rad), printed to the same resolution as mm and degrees;
    // of the two vectors of one rotation (θ·u and (θ − 2π)·u), the one nearer the written.
    for (int k = 0; k < 3; ++k)
      expected[k] =
          out.number(f[k], corrected.base_T_tcp.p[k] / 1000, options.position_decimals + 3);
    const Eigen::AngleAxisd aa(corrected.base_T_tcp.R);
    const Eigen::Vector3d written(f[3].value, f[4].value, f[5].value);
    Eigen::Vector3d r = aa.angle() * aa.axis();
    const Eigen::Vector3d other = (aa.angle() - 2 * std::numbers::pi) * aa.axis();
    if ((other - written).norm() < (r - written).norm()) r = other;
    for (int k = 0; k < 3; ++k)
      expected[3 + k] = out.number(f[3 + k], r[k], options.angle_decimals + 3);
    return expected;
  }
  // Yaskawa: the controller's resolution, 1 µm and 0.0001°.
  const bool jbi = language == ProgramLanguage::Jbi;
  for (int k = 0; k < 3; ++k)
    expected[k] = out.number(f[k], corrected.base_T_tcp.p[k], jbi ? 3 : options.position_decimals);
  if (language == ProgramLanguage::Rapid) {
    Eigen::Quaterniond q(corrected.base_T_tcp.R);
    // Same hemisphere as the written quaternion, so an unchanged rotation prints unchanged.
    const Eigen::Vector4d written =
        Eigen::Vector4d(f[3].value, f[4].value, f[5].value, f[6].value).normalized();
    if (Eigen::Vector4d(q.w(), q.x(), q.y(), q.z()).dot(written) < 0) q.coeffs() *= -1;
    const double wxyz[4] = {q.w(), q.x(), q.y(), q.z()};
    for (int k = 0; k < 4; ++k)
      expected[3 + k] = out.number(f[3 + k], wxyz[k], options.quaternion_decimals, written[k]);
  } else {
    // KRL (A, B, C), Fanuc (W, P, R) and Yaskawa (Rx, Ry, Rz) = (C, B, A): R = Rz(A)·Ry(B)·Rx(C).
    Eigen::Vector3d abc = euler_angles_deg(corrected.base_T_tcp.R, EulerConvention::ZyxABC);
    if (language == ProgramLanguage::FanucLs || jbi) abc = abc.reverse().eval();
    for (int k = 0; k < 3; ++k)
      expected[3 + k] = out.number(f[3 + k], near_written(abc[k], f[3 + k].value),
                                   jbi ? 4 : options.angle_decimals);
  }
  // Fanuc CONFIG and Yaskawa RCONF are kept as written (filter_program checks they still hold).
  if (!corrected.config.empty() && language != ProgramLanguage::FanucLs && !jbi) {
    const size_t first = language == ProgramLanguage::Rapid ? 7 : 6;
    for (size_t k = 0; k < corrected.config.size() && first + k < f.size(); ++k)
      expected[first + k] = out.integer(f[first + k], corrected.config[k]);
  }
  return expected;
}

/// The rewritten text must parse to the same program: the same points at the same places,
/// each field holding exactly the value written into it (issue 21: a rewrite that corrupts
/// the text must never reach the disk).
void check_reparse(const std::vector<PointSite>& after, const std::vector<PointSite>& before,
                   const std::vector<std::vector<double>>& expected, const std::string& file) {
  const auto fail = [&](const ProgramPoint& p, const std::string& what) {
    throw std::logic_error(fmt::format(
        "{}:{}:{}: the corrected program does not read back as written ({}); nothing written", file,
        p.line, p.column, what));
  };
  if (after.size() != before.size())
    fail(before.empty() ? ProgramPoint{} : before.back().point,
         fmt::format("{} points instead of {}", after.size(), before.size()));
  for (size_t i = 0; i < before.size(); ++i) {
    const ProgramPoint& a = before[i].point;
    const ProgramPoint& b = after[i].point;
    // Columns move when an earlier number on the same line is rewritten longer or shorter.
    if (a.line != b.line || a.name != b.name || a.is_joint_target != b.is_joint_target ||
        after[i].fields.size() != expected[i].size())
      fail(a, "another point at this place");
    for (size_t k = 0; k < expected[i].size(); ++k)
      if (after[i].fields[k].value != expected[i][k])
        fail(a, fmt::format("field {} reads {} instead of {}", k + 1, after[i].fields[k].value,
                            expected[i][k]));
  }
}

/// The program's own tool or frame definitions merged with the user's (upper-case names);
/// a name defined in both with other values is refused.
std::map<std::string, Pose<double>> definitions(const std::map<std::string, Pose<double>>& program,
                                                const std::map<std::string, Pose<double>>& given,
                                                const char* what, const std::string& file) {
  std::map<std::string, Pose<double>> out = program;
  for (const auto& [name, pose] : given) {
    const auto [it, added] = out.emplace(detail::upper(name), pose);
    if (!added && ((it->second.p - pose.p).norm() > 1e-3 || (it->second.R - pose.R).norm() > 1e-6))
      throw InputError(SourceLocation{file, 0, 0, name},
                       fmt::format("{} '{}' is defined in the program and in the frames file with "
                                   "other values",
                                   what, name));
  }
  return out;
}

/// How each language names its tools and frames, and which names are the flange and the base
/// frame: RAPID tool0 / wobj0, KRL tool 0 / base 0 ($ROBROOT taken as the world, a robot not
/// on a track), Fanuc UT[0] (faceplate) / UF[0] (world = robot base).
struct Naming {
  const char* flange;
  const char* base_frame;
  const char* frame_kind;
};
const Naming& naming(ProgramLanguage language) {
  static const Naming kRapid{"TOOL0", "WOBJ0", "work object"};
  static const Naming kKrl{"TOOL_DATA[0]", "BASE_DATA[0]", "base"};
  static const Naming kLs{"UT[0]", "UF[0]", "user frame"};
  static const Naming kUr{"", "", "frame"};  // no frames; no set_tcp: the installation's TCP
  // Yaskawa: every tool number is a tool file entry (none is the flange by definition); the
  // robot frame is the base.
  static const Naming kJbi{"", "", "user frame"};
  return language == ProgramLanguage::Rapid     ? kRapid
         : language == ProgramLanguage::Krl     ? kKrl
         : language == ProgramLanguage::FanucLs ? kLs
         : language == ProgramLanguage::Jbi     ? kJbi
                                                : kUr;
}

/// The pose of a named tool or frame; empty and `identity_name` (tool0, wobj0) are identity.
/// A name the program makes active without a value the scan can know (`unknown`) is refused
/// with the scan's reason, before any frames-file value of that name.
/// Where a point is (built when needed: it copies the file name).
SourceLocation location(const std::string& file, const ProgramPoint& point) {
  return {file, point.line, point.column, point.name};
}

Pose<double> resolve(const std::map<std::string, Pose<double>>& known,
                     const std::map<std::string, std::string>& unknown, const std::string& name,
                     const char* identity_name, const char* what, const std::string& file,
                     const ProgramPoint& at) {
  if (name.empty() || name == identity_name) return Pose<double>{};
  if (const auto why = unknown.find(name); why != unknown.end())
    throw InputError(location(file, at),
                     fmt::format("unknown {} '{}': {}", what, name, why->second));
  const auto it = known.find(name);
  if (it == known.end())
    throw InputError(location(file, at),
                     fmt::format("unknown {} '{}': the program does not define it with "
                                 "literal values; give it in a frames file",
                                 what, name));
  return it->second;
}

}  // namespace

std::vector<ProgramPoint> read_program_points(std::string_view text, ProgramLanguage language,
                                              const std::string& file,
                                              const ProgramFilterOptions& options) {
  std::vector<ProgramPoint> points;
  for (PointSite& site : scan(text, language, file, options).sites)
    points.push_back(std::move(site.point));
  return points;
}

namespace {

/// One file's points corrected and rewritten: the text, and what each point's fields must
/// read back as.
struct Correction {
  ProgramFilterResult result;
  std::vector<std::vector<double>> expected;
};

/// `row_prefix` starts each confidence row (a module's rows name their file).
Correction correct_sites(std::string_view text, const detail::ProgramScan& scanned,
                         const std::map<std::string, Pose<double>>& tools,
                         const std::map<std::string, Pose<double>>& frames,
                         ProgramLanguage language, const std::string& file,
                         const ProgramFilterOptions& options, const PointCorrector& corrector,
                         const std::string& row_prefix) {
  Rewriter out(text);
  Correction c;
  ProgramFilterResult& result = c.result;
  std::vector<std::vector<double>>& expected = c.expected;
  result.uncorrected = scanned.unresolved;
  expected.reserve(scanned.sites.size());
  for (const PointSite& site : scanned.sites) {
    // The corrector works in the base frame with the active tool.
    ProgramPoint point = site.point;
    const Naming& names = naming(language);
    const Pose<double> base_T_frame = resolve(frames, scanned.unknown_frames, point.frame,
                                              names.base_frame, names.frame_kind, file, site.point);
    if (!point.tool.empty())
      point.flange_T_tcp = resolve(tools, scanned.unknown_frames, point.tool, names.flange, "tool",
                                   file, site.point);
    point.base_T_tcp = base_T_frame * point.base_T_tcp;
    CorrectedPoint corrected = corrector(point);
    if (corrected.failure.empty() &&
        (language == ProgramLanguage::FanucLs || language == ProgramLanguage::Jbi) &&
        !corrected.config.empty() && corrected.config != point.config)
      corrected.failure =
          language == ProgramLanguage::FanucLs
              ? fmt::format(
                    "the corrected target needs CONFIG [{}], not the written [{}] (flip, "
                    "down, back, turns): rewrite the CONFIG by hand",
                    fmt::join(corrected.config, ","), fmt::join(point.config, ","))
              : fmt::format(
                    "the corrected target needs ///RCONF {}, not the written {} (no-flip, "
                    "lower, rear, R, T, S >= 180): give it its own ///RCONF by hand",
                    fmt::join(corrected.config, ","), fmt::join(point.config, ","));
    if (corrected.failure.empty() && language == ProgramLanguage::Jbi && point.is_joint_target) {
      for (int k = 0; k < kJointCount; ++k)
        if (!(std::abs(corrected.joints_deg[k] *
                       options.pulses_per_degree[static_cast<size_t>(k)]) < 2e9))
          corrected.failure = fmt::format("axis {}: {} deg is beyond a 32-bit pulse count", k + 1,
                                          corrected.joints_deg[k]);
    }
    if (corrected.failure.empty() &&
        (!corrected.base_T_tcp.p.allFinite() || !corrected.base_T_tcp.R.allFinite() ||
         !corrected.joints_deg.allFinite()))
      corrected.failure = "the corrected point is not finite (NaN or infinite)";
    if (!corrected.failure.empty()) {
      if (!options.keep_going) throw InputError(location(file, site.point), corrected.failure);
      result.uncorrected.push_back({location(file, site.point).describe(), corrected.failure});
      std::vector<double> unchanged;
      for (const NumberField& f : site.fields) unchanged.push_back(f.value);
      expected.push_back(std::move(unchanged));
      continue;
    }
    if (!site.assumption.empty()) {
      result.assumed.push_back({location(file, site.point).describe(), site.assumption});
    } else if (point.tool.empty() && !point.is_joint_target &&
               (language == ProgramLanguage::Rapid || language == ProgramLanguage::Krl ||
                language == ProgramLanguage::Jbi))
      result.assumed.push_back(
          {location(file, site.point).describe(),
           language == ProgramLanguage::Rapid
               ? "no Move instruction of this module uses it: corrected for the default tool "
                 "in wobj0"
           : language == ProgramLanguage::Krl
               ? "no FDAT or BAS(#TOOL/#BASE) / $TOOL / $BASE of this file names its tool and "
                 "base: corrected for the default tool in the robot's base frame"
               : "no ///TOOL line before it: corrected for the default tool (--tool)"});
    corrected.base_T_tcp = base_T_frame.inverse() * corrected.base_T_tcp;
    expected.push_back(rewrite(out, site, corrected, language, options));
    ++(site.point.is_joint_target ? result.joint_points : result.cartesian_points);
    auto row = std::back_inserter(result.confidence_csv);
    // Compiled formats: one row per point, parsed once at build time.
    fmt::format_to(row, FMT_COMPILE("{}{},{},{},"), row_prefix, site.point.line, site.point.column,
                   site.point.name);
    if (corrected.confidence95_mm)
      fmt::format_to(row, FMT_COMPILE("{:.4f}"), *corrected.confidence95_mm);
    result.confidence_csv += '\n';
  }
  result.text = out.apply();
  return c;
}

}  // namespace

ProgramFilterResult filter_program(std::string_view text, ProgramLanguage language,
                                   const std::string& file, const ProgramFilterOptions& options,
                                   const PointCorrector& corrector) {
  const detail::ProgramScan scanned = scan(text, language, file, options);
  Correction c =
      correct_sites(text, scanned, definitions(scanned.tools, options.tools, "tool", file),
                    definitions(scanned.frames, options.frames, "frame", file), language, file,
                    options, corrector, "");
  c.result.confidence_csv = "line,column,name,confidence95_mm\n" + c.result.confidence_csv;
  check_reparse(scan(c.result.text, language, file, options).sites, scanned.sites, c.expected,
                file);
  return c.result;
}

std::vector<ProgramPoint> read_krl_module_points(std::string_view src, std::string_view dat,
                                                 const std::string& src_file,
                                                 const std::string& dat_file,
                                                 const ProgramFilterOptions& options) {
  detail::KrlModuleScan scanned = detail::scan_krl_module(src, dat, src_file, dat_file, options);
  std::vector<ProgramPoint> points;
  for (auto* part : {&scanned.src, &scanned.dat})
    for (PointSite& site : part->sites) points.push_back(std::move(site.point));
  return points;
}

ProgramFilterResult filter_krl_module(std::string_view src, std::string_view dat,
                                      const std::string& src_file, const std::string& dat_file,
                                      const ProgramFilterOptions& options,
                                      const PointCorrector& corrector) {
  const detail::KrlModuleScan scanned =
      detail::scan_krl_module(src, dat, src_file, dat_file, options);
  const auto tools = definitions(scanned.src.tools, options.tools, "tool", src_file);
  const auto frames = definitions(scanned.src.frames, options.frames, "frame", src_file);
  const auto correct = [&](std::string_view text, const detail::ProgramScan& part,
                           const std::string& file) {
    return correct_sites(text, part, tools, frames, ProgramLanguage::Krl, file, options, corrector,
                         file + ",");
  };
  Correction s = correct(src, scanned.src, src_file);
  Correction d = correct(dat, scanned.dat, dat_file);
  // The .dat's points do not depend on the .src (scanned first, alone); the .src's depend on
  // the .dat's declarations, so a changed .src is read back with its .dat (one module scan
  // checks both files).
  if (s.result.text == src) {
    check_reparse(detail::scan_krl(d.result.text, dat_file, options).sites, scanned.dat.sites,
                  d.expected, dat_file);
  } else {
    const detail::KrlModuleScan again =
        detail::scan_krl_module(s.result.text, d.result.text, src_file, dat_file, options);
    check_reparse(again.dat.sites, scanned.dat.sites, d.expected, dat_file);
    check_reparse(again.src.sites, scanned.src.sites, s.expected, src_file);
  }
  ProgramFilterResult result = std::move(s.result);
  result.dat_text = std::move(d.result.text);
  result.cartesian_points += d.result.cartesian_points;
  result.joint_points += d.result.joint_points;
  for (const auto list : {&ProgramFilterResult::uncorrected, &ProgramFilterResult::assumed})
    (result.*list).insert((result.*list).end(), (d.result.*list).begin(), (d.result.*list).end());
  result.confidence_csv =
      "file,line,column,name,confidence95_mm\n" + result.confidence_csv + d.result.confidence_csv;
  return result;
}

}  // namespace robcal

namespace robcal {

std::string krl_companion_path(const std::string& path) {
  const std::filesystem::path p(path);
  const std::string ext = p.extension().string();
  const bool src = detail::iequals(ext, ".src");
  if (!src && !detail::iequals(ext, ".dat")) return "";
  std::string other = src ? ".dat" : ".src";
  if (detail::upper(ext) == ext) other = detail::upper(other);
  return std::filesystem::path(p).replace_extension(other).string();
}

namespace {

/// Writes `a` then `b`, each atomically; when `b` fails, `a` is put back as it was (removed
/// when it did not exist): the two files of a module are written both or none.
void write_pair_atomically(const std::string& a, std::string_view a_text, const std::string& b,
                           std::string_view b_text) {
  std::error_code ec;
  std::optional<std::string> previous;
  if (std::filesystem::is_regular_file(a, ec)) previous = read_text_file(a);
  write_file_atomically(a, a_text);
  try {
    write_file_atomically(b, b_text);
  } catch (...) {
    if (previous)
      write_file_atomically(a, *previous);
    else
      std::filesystem::remove(a, ec);
    throw;
  }
}

}  // namespace

ProgramFilterResult filter_program_file(const std::string& in, const std::string& out,
                                        const ProgramFilterOptions& options,
                                        const PointCorrector& corrector,
                                        const std::string& confidence_out) {
  const ProgramLanguage language = program_language_from_path(in);
  if (program_language_from_path(out) != language ||
      (language == ProgramLanguage::Krl &&
       !detail::iequals(std::filesystem::path(in).extension().string(),
                        std::filesystem::path(out).extension().string())))
    throw InputError({out, 0, 0, "--out"}, "the output must be the same kind of program as --in");
  // A KUKA module: the .src with its .dat beside it, read and written together.
  std::error_code ec;
  const std::string companion = krl_companion_path(in);
  const bool module = !companion.empty() && std::filesystem::is_regular_file(companion, ec);
  const std::string out_companion = module ? krl_companion_path(out) : "";
  // Same path after resolving `..` and links, or the same file under another name.
  const auto resolved = [](const std::string& path) {
    std::error_code e;
    std::filesystem::path p = std::filesystem::weakly_canonical(path, e);
    return e ? std::filesystem::path(path).lexically_normal() : p;
  };
  for (const std::string& o : {out, out_companion, confidence_out})
    for (const std::string& i : {in, module ? companion : in}) {
      if (!o.empty() && (resolved(o) == resolved(i) || std::filesystem::equivalent(o, i, ec)))
        throw InputError({o, 0, 0, o == confidence_out ? "--confidence-out" : "--out"},
                         i == in ? "the output is the input program: give a new file (the "
                                   "original is kept)"
                                 : "the output is the input module's " + i +
                                       ": give a new file (the original is kept)");
    }
  if (!module) {
    ProgramFilterResult result =
        filter_program(read_text_file(in), language, in, options, corrector);
    write_file_atomically(out, result.text);
    if (!confidence_out.empty()) write_file_atomically(confidence_out, result.confidence_csv);
    return result;
  }
  const bool in_is_src = detail::iequals(std::filesystem::path(in).extension().string(), ".src");
  const std::string& src = in_is_src ? in : companion;
  const std::string& dat = in_is_src ? companion : in;
  ProgramFilterResult result =
      filter_krl_module(read_text_file(src), read_text_file(dat), src, dat, options, corrector);
  const std::string& out_src = in_is_src ? out : out_companion;
  const std::string& out_dat = in_is_src ? out_companion : out;
  write_pair_atomically(out_dat, *result.dat_text, out_src, result.text);
  if (!confidence_out.empty()) write_file_atomically(confidence_out, result.confidence_csv);
  return result;
}

}  // namespace robcal
