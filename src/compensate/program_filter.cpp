#include "robcal/compensate/program_filter.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <filesystem>

#include "program_scan.hpp"
#include "robcal/core/error.hpp"
#include "robcal/kinematics/orientation.hpp"

namespace robcal {
namespace {

using detail::NumberField;
using detail::PointSite;

std::vector<PointSite> scan(std::string_view text, ProgramLanguage language,
                            const std::string& file, const ProgramFilterOptions& options) {
  return language == ProgramLanguage::Rapid ? detail::scan_rapid(text, file, options)
                                            : detail::scan_krl(text, file, options);
}

/// Collects the replacements of one program, in text order.
class Rewriter {
 public:
  explicit Rewriter(std::string_view text) : text_(text) {}

  /// Replaces a number with `value` printed with `decimals`, unless the printed value equals
  /// the written one (then the original bytes stay).
  void number(const NumberField& field, double value, int decimals) {
    number(field, value, decimals, field.value);
  }
  /// `reference` is the written value as read (a normalised quaternion differs from its text).
  void number(const NumberField& field, double value, int decimals, double reference) {
    const double half_unit = 0.5 * std::pow(10.0, -decimals);
    if (std::abs(value - reference) < half_unit) return;
    std::string printed = fmt::format("{:.{}f}", value, decimals);
    if (printed.find_first_not_of("-0.") == std::string::npos)
      printed = printed.substr(printed[0] == '-');
    edits_.push_back({field.begin, field.end, std::move(printed)});
  }

  void integer(const NumberField& field, int value) {
    if (value == static_cast<int>(field.value)) return;
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
  }

  std::string apply() const {
    std::string out;
    out.reserve(text_.size() + edits_.size() * 4);
    size_t at = 0;
    for (const Edit& e : edits_) {
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

void rewrite(Rewriter& out, const PointSite& site, const CorrectedPoint& corrected,
             ProgramLanguage language, const ProgramFilterOptions& options) {
  const auto& f = site.fields;
  if (site.point.is_joint_target) {
    for (int k = 0; k < kJointCount; ++k)
      out.number(f[k], corrected.joints_deg[k], options.angle_decimals);
    return;
  }
  for (int k = 0; k < 3; ++k)
    out.number(f[k], corrected.base_T_tcp.p[k], options.position_decimals);
  if (language == ProgramLanguage::Rapid) {
    Eigen::Quaterniond q(corrected.base_T_tcp.R);
    // Same hemisphere as the written quaternion, so an unchanged rotation prints unchanged.
    const Eigen::Vector4d written =
        Eigen::Vector4d(f[3].value, f[4].value, f[5].value, f[6].value).normalized();
    if (Eigen::Vector4d(q.w(), q.x(), q.y(), q.z()).dot(written) < 0) q.coeffs() *= -1;
    const double wxyz[4] = {q.w(), q.x(), q.y(), q.z()};
    for (int k = 0; k < 4; ++k)
      out.number(f[3 + k], wxyz[k], options.quaternion_decimals, written[k]);
  } else {
    const Eigen::Vector3d abc = euler_angles_deg(corrected.base_T_tcp.R, EulerConvention::ZyxABC);
    for (int k = 0; k < 3; ++k)
      out.number(f[3 + k], near_written(abc[k], f[3 + k].value), options.angle_decimals);
  }
  if (!corrected.config.empty()) {
    const size_t first = language == ProgramLanguage::Rapid ? 7 : 6;
    for (size_t k = 0; k < corrected.config.size() && first + k < f.size(); ++k)
      out.integer(f[first + k], corrected.config[k]);
  }
}

}  // namespace

ProgramLanguage program_language_from_path(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return std::tolower(c); });
  if (ext == ".mod" || ext == ".modx" || ext == ".prg" || ext == ".sys")
    return ProgramLanguage::Rapid;
  if (ext == ".src" || ext == ".dat") return ProgramLanguage::Krl;
  throw InputError(SourceLocation{path, 0, 0, ""},
                   "unknown program type: expected an ABB RAPID module (.mod, .modx, .prg, .sys) "
                   "or a KUKA KRL file (.src, .dat)");
}

std::vector<ProgramPoint> read_program_points(std::string_view text, ProgramLanguage language,
                                              const std::string& file,
                                              const ProgramFilterOptions& options) {
  std::vector<ProgramPoint> points;
  for (PointSite& site : scan(text, language, file, options))
    points.push_back(std::move(site.point));
  return points;
}

ProgramFilterResult filter_program(std::string_view text, ProgramLanguage language,
                                   const std::string& file, const ProgramFilterOptions& options,
                                   const PointCorrector& corrector) {
  const std::vector<PointSite> sites = scan(text, language, file, options);
  Rewriter out(text);
  ProgramFilterResult result;
  for (const PointSite& site : sites) {
    const CorrectedPoint corrected = corrector(site.point);
    if (!corrected.failure.empty())
      throw InputError(SourceLocation{file, site.point.line, site.point.column, site.point.name},
                       corrected.failure);
    rewrite(out, site, corrected, language, options);
    ++(site.point.is_joint_target ? result.joint_points : result.cartesian_points);
  }
  result.text = out.apply();
  return result;
}

}  // namespace robcal
