// Universal Robots URScript (.script): measurement programs and their joint moves read back.
//
// Grammar constraints relied on: a program is one `def name():` ... `end` block (names are
// identifiers; indentation is not significant); joint positions are lists of six floats in
// radians, `movej([q1, ..., q6], a=rad/s², v=rad/s)`, which stops at the target (r = 0:
// no blend, a fine point); `#` comments run to the end of the line; textmsg(s1, s2) writes
// to the controller's log. Floats are doubles: 10 decimals of a radian keep 1e-6° exactly.

#include <fmt/format.h>

#include <cctype>
#include <map>
#include <numbers>
#include <unordered_map>

#include <Eigen/Geometry>

#include "measurement_writers.hpp"
#include "program_scan.hpp"
#include "robcal/core/error.hpp"
#include "robcal/core/units.hpp"

namespace robcal::detail {

std::string write_urscript_measurement(const MeasurementPart& part) {
  const MeasurementProgramRequest& r = part.request;
  // The slowest joints of the UR arms reach π rad/s: the percentage is of that.
  const double v = r.joint_speed_percent / 100.0 * std::numbers::pi;
  const auto movej = [&](const Vector6d& q_deg) {
    const Vector6d q = q_deg * kDegToRad;
    return fmt::format(
        "  movej([{:.10f}, {:.10f}, {:.10f}, {:.10f}, {:.10f}, {:.10f}], a=1.0, v={:.4f})\n", q[0],
        q[1], q[2], q[3], q[4], q[5], v);
  };
  std::string out = fmt::format("def {}():\n", part.program) +
                    header_comment(part, "  #", "reached without blending");
  for (const Visit& visit : part.visits) {
    const Vector6d& q = visit.target_deg;
    out += fmt::format("  # {}\n", visit.label()) +
           (visit.approach ? movej(visit.approach_deg) : "") + movej(q);
    if (!visit.measure) continue;
    out += fmt::format("  sleep({:.2f})\n", r.settle_s);
    switch (r.hook) {
      case MeasurementHook::WaitInput:
        out +=
            fmt::format("  while not get_standard_digital_in({}):\n    sync()\n  end\n", r.signal);
        break;
      case MeasurementHook::PulseOutput:
        out += fmt::format(
            "  set_standard_digital_out({0}, True)\n  sleep(0.5)\n"
            "  set_standard_digital_out({0}, False)\n",
            r.signal);
        break;
      case MeasurementHook::LogLine:
        out += fmt::format(
            "  textmsg(\"robcal config {} joints \", \"{:.6f} {:.6f} {:.6f} {:.6f} {:.6f} "
            "{:.6f}\")\n",
            visit.name, q[0], q[1], q[2], q[3], q[4], q[5]);
        break;
    }
  }
  return out + "end\n";
}

std::vector<JointMove> read_urscript_joint_moves(const std::string& text, const std::string& file) {
  std::vector<JointMove> moves;
  int line = 1;
  size_t line_start = 0;
  for (size_t at = 0; at < text.size(); ++at) {
    const char c = text[at];
    if (c == '\n') {
      ++line;
      line_start = at + 1;
    } else if (c == '#') {
      while (at + 1 < text.size() && text[at + 1] != '\n') ++at;
    } else if (c == '"') {
      // A string (where "movej(" is text): skip to its closing quote, or stop at the line end.
      const size_t close = text.find_first_of("\"\n", at + 1);
      if (close == std::string::npos) break;
      at = text[close] == '"' ? close : close - 1;
    } else if (text.compare(at, 6, "movej(") == 0 &&
               (at == 0 ||
                !(std::isalnum(static_cast<unsigned char>(text[at - 1])) || text[at - 1] == '_'))) {
      const auto fail = [&](size_t pos, const std::string& what) {
        throw InputError(SourceLocation{file, line, static_cast<int>(pos - line_start) + 1, ""},
                         what);
      };
      const auto skip_blanks = [&](size_t pos) {
        while (pos < text.size() && (text[pos] == ' ' || text[pos] == '\t')) ++pos;
        return pos;
      };
      size_t pos = skip_blanks(at + 6);
      // movej(p[...]) is a pose (inverse kinematics on the controller), not a joint move.
      if (text.compare(pos, 2, "p[") == 0) {
        at = pos;
        continue;
      }
      if (pos >= text.size() || text[pos] != '[')
        fail(pos, "movej: expected a joint list [q1, ..., q6] in radians");
      JointMove move;
      move.line = line;
      ++pos;
      for (int j = 0; j < kJointCount; ++j) {
        pos = skip_blanks(pos);
        move.joints_deg[j] = rad2deg(read_number(text, pos, file, line, line_start));
        pos = skip_blanks(pos);
        const char want = j + 1 < kJointCount ? ',' : ']';
        if (pos >= text.size() || text[pos] != want)
          fail(pos, fmt::format("movej: expected '{}' after joint {}", want, j + 1));
        ++pos;
      }
      moves.push_back(move);
      at = pos - 1;
    }
  }
  return moves;
}

}  // namespace robcal::detail

// URScript filtering. Targets: a pose literal p[x, y, z, rx, ry, rz] (metres, rotation vector
// in radians) that is the first argument of movel/movej/movep/movec (movec: the first two)
// or the value of an assignment `name = p[...]`; with `joints`, the joint list of
// `movej([q1, ..., q6], ...)` (radians). The tool of a literal written in a motion is the last
// set_tcp(p[...]) before it (the flange before any); an assigned pose takes the tool of the
// motions that name the variable (`movel(wp)`: the assignment of `wp` last before it in the
// text, or every assignment of `wp` when none is before it), as RAPID and KRL declarations do:
// one value used under two tools is refused, and a pose no motion names keeps the tool active
// where it is assigned, listed as assumed. Pose literals elsewhere (pose_trans offsets, set_tcp
// itself) are relative or tool data and stay as written. There are no user frames in the
// language: the targets are in the robot's base frame.
namespace robcal::detail {
namespace {

class UrScanner {
 public:
  UrScanner(std::string_view text, const std::string& file, const ProgramFilterOptions& options)
      : text_(text), file_(file), options_(options) {}

  ProgramScan run() {
    for (at_ = 0; at_ < text_.size(); ++at_) {
      const char c = text_[at_];
      if (c == '\n') {
        ++line_;
        line_start_ = at_ + 1;
      } else if (c == '#') {
        while (at_ + 1 < text_.size() && text_[at_ + 1] != '\n') ++at_;
      } else if (c == '"' || c == '\'') {
        const size_t close = text_.find_first_of(c == '"' ? "\"\n" : "'\n", at_ + 1);
        if (close == std::string_view::npos || text_[close] == '\n')
          throw InputError(SourceLocation{file_, line_, column(at_), ""}, "unterminated string");
        at_ = close;
      } else if (std::isalpha(static_cast<unsigned char>(c)) || c == '_') {
        word();
      }
    }
    assign_uses();
    return std::move(out_);
  }

 private:
  int column(size_t at) const { return static_cast<int>(at - line_start_) + 1; }

  size_t skip_blanks(size_t at) const {
    while (at < text_.size() && (text_[at] == ' ' || text_[at] == '\t')) ++at;
    return at;
  }

  void word() {
    const size_t begin = at_;
    while (at_ < text_.size() &&
           (std::isalnum(static_cast<unsigned char>(text_[at_])) || text_[at_] == '_'))
      ++at_;
    const std::string_view w = text_.substr(begin, at_ - begin);
    const size_t next = skip_blanks(at_);
    --at_;  // the loop's ++ lands on the character after the word
    if (begin > 0 && text_[begin - 1] == '.') return;
    if (w == "set_tcp" && text_.compare(next, 1, "(") == 0) {
      const size_t open = skip_blanks(next + 1);
      if (text_.compare(open, 2, "p[") != 0) {
        tool_ = fmt::format("set_tcp at line {}", line_);  // not a literal: unknown
        return;
      }
      NumberFields f = pose_literal(open);
      tool_ = fmt::format("SET_TCP@{}", line_);
      out_.tools[tool_] = pose_of(f);
      at_ = f.back().end - 1;
    } else if ((w == "movel" || w == "movej" || w == "movep" || w == "movec") &&
               text_.compare(next, 1, "(") == 0) {
      size_t arg = skip_blanks(next + 1);
      const int targets = w == "movec" ? 2 : 1;
      for (int k = 0; k < targets; ++k) {
        size_t after = 0;  // the first character after the target argument
        if (text_.compare(arg, 2, "p[") == 0) {
          const NumberFields f = pose_literal(arg);
          add_target(f, "", arg);
          after = f.back().end;
        } else if (w == "movej" && text_.compare(arg, 1, "[") == 0) {
          if (!options_.joints) return;  // joint targets only with `joints`
          const NumberFields f = joint_list(arg);
          add_joint_target(f, arg);
          after = f.back().end;
        } else if (const size_t end = identifier_end(arg); end > arg) {
          const size_t close = skip_blanks(end);
          // A plain variable (not a call, not an expression): a use of its assigned pose.
          if (close >= text_.size() || !(text_[close] == ',' || text_[close] == ')')) return;
          use(std::string(text_.substr(arg, end - arg)), arg);
          arg = close;
          at_ = arg - 1;
          if (k + 1 == targets) {
            motion_arguments(arg, w);
            return;
          }
          if (text_[arg] != ',') return;
          arg = skip_blanks(arg + 1);
          continue;
        } else {
          return;  // an expression
        }
        arg = skip_blanks(skip_blanks(after) + 1);  // after the ']'
        if (k + 1 == targets) {
          at_ = arg - 1;
          motion_arguments(arg, w);
          return;
        }
        if (arg >= text_.size() || text_[arg] != ',') return;
        arg = skip_blanks(arg + 1);
        at_ = arg - 1;
      }
    } else if (text_.compare(next, 1, "=") == 0 && text_.compare(next, 2, "==") != 0) {
      const size_t value = skip_blanks(next + 1);
      if (text_.compare(value, 2, "p[") != 0) return;
      const NumberFields f = pose_literal(value);
      assignments_[std::string(w)].push_back(out_.sites.size());
      add_target(f, std::string(w), value);
      at_ = f.back().end - 1;
    }
  }

  size_t identifier_end(size_t at) const {
    if (at >= text_.size() ||
        !(std::isalpha(static_cast<unsigned char>(text_[at])) || text_[at] == '_'))
      return at;
    while (at < text_.size() &&
           (std::isalnum(static_cast<unsigned char>(text_[at])) || text_[at] == '_'))
      ++at;
    return at;
  }

  /// A motion naming a variable: the use of its last assignment so far, with the tool here.
  void use(const std::string& name, size_t at) {
    const Use u{tool_, line_, column(at)};
    const auto it = assignments_.find(name);
    if (it == assignments_.end())
      later_uses_[name].push_back(u);
    else
      uses_[it->second.back()].push_back(u);
  }

  // Each assigned pose takes the tool of the motions that use it (file comment above).
  void assign_uses() {
    for (const auto& [name, list] : later_uses_)
      if (const auto it = assignments_.find(name); it != assignments_.end())
        for (size_t site : it->second)
          uses_[site].insert(uses_[site].end(), list.begin(), list.end());
    for (const auto& [name, sites] : assignments_)
      for (size_t index : sites) {
        PointSite& site = out_.sites[index];
        const auto found = uses_.find(index);
        if (found == uses_.end()) {
          site.assumption = fmt::format(
              "no movel/movej/movep/movec names '{}' after this assignment: corrected for the "
              "tool active here ({})",
              name,
              site.point.tool.empty() ? "no set_tcp before it: the default tool" : site.point.tool);
          continue;
        }
        const Use& first = found->second.front();
        for (const Use& u : found->second)
          if (u.tool != first.tool)
            throw InputError(
                SourceLocation{file_, site.point.line, site.point.column, name},
                fmt::format("used under {} at {}:{}:{} and under {} at {}:{}:{}: one corrected "
                            "value cannot serve both; give each use its own pose",
                            tool_label(first.tool), file_, first.line, first.column,
                            tool_label(u.tool), file_, u.line, u.column));
        site.point.tool = first.tool;
      }
  }

  static std::string tool_label(const std::string& tool) {
    return tool.empty() ? std::string("the default tool (no set_tcp before it)") : tool;
  }

  // The arguments after a motion's last target, up to its ')': positional values or the
  // keywords a, v, t, r (movec also mode), `name=value`, comma-separated. A malformed one
  // (`a==1.2`, `a=`, `,,`, a missing comma, `acc=1`) makes the controller refuse the script, so
  // it is refused here rather than passed on corrected. Only the motion's own line is read.
  void motion_arguments(size_t at, std::string_view motion) {
    const auto fail = [&](size_t pos, const std::string& what) {
      throw InputError(SourceLocation{file_, line_, column(pos), ""},
                       fmt::format("{}: {}", motion, what));
    };
    const auto ends_line = [&](size_t pos) {
      return pos >= text_.size() || text_[pos] == '\n' || text_[pos] == '\r' || text_[pos] == '#';
    };
    for (;;) {
      if (ends_line(at)) return;
      if (text_[at] == ')') return;
      if (text_[at] != ',') fail(at, "expected ',' or ')' after the target");
      at = skip_blanks(at + 1);
      size_t name_end = at;
      while (name_end < text_.size() &&
             (std::isalnum(static_cast<unsigned char>(text_[name_end])) || text_[name_end] == '_'))
        ++name_end;
      const size_t eq = skip_blanks(name_end);
      if (name_end > at && eq < text_.size() && text_[eq] == '=') {
        const std::string_view name = text_.substr(at, name_end - at);
        if (!(name == "a" || name == "v" || name == "t" || name == "r" ||
              (motion == "movec" && name == "mode")))
          fail(at, fmt::format("unknown argument '{}': expected a, v, t or r{}", name,
                               motion == "movec" ? " or mode" : ""));
        at = skip_blanks(eq + 1);
      }
      // The value: up to ',' or ')' outside brackets.
      size_t end = at;
      int depth = 0;
      while (!ends_line(end) && !(depth == 0 && (text_[end] == ',' || text_[end] == ')'))) {
        if (text_[end] == '(' || text_[end] == '[') ++depth;
        if (text_[end] == ')' || text_[end] == ']') --depth;
        ++end;
      }
      if (end == at || text_[at] == '=' ||
          text_.substr(at, end - at).find_first_not_of(" \t") == std::string_view::npos)
        fail(at, fmt::format("expected a value, found '{}'",
                             ends_line(at) ? "end of line" : std::string(1, text_[at])));
      at = end;
    }
  }

  using NumberFields = std::vector<NumberField>;

  // p[x, y, z, rx, ry, rz] at `at`: six number literals, read whole.
  NumberFields pose_literal(size_t at) {
    NumberFields f;
    size_t pos = at + 2;
    for (int k = 0; k < 6; ++k) {
      pos = skip_blanks(pos);
      f.push_back(read_number_field(text_, pos, file_, line_, line_start_));
      pos = skip_blanks(pos);
      const char want = k < 5 ? ',' : ']';
      if (pos >= text_.size() || text_[pos] != want)
        throw InputError(
            SourceLocation{file_, line_, column(pos), ""},
            fmt::format("pose p[x, y, z, rx, ry, rz]: expected '{}' after value {}", want, k + 1));
      ++pos;
    }
    return f;
  }

  // [q1, ..., q6] at `at` (radians): six number literals, read whole.
  NumberFields joint_list(size_t at) {
    NumberFields f;
    size_t pos = at + 1;
    for (int k = 0; k < kJointCount; ++k) {
      pos = skip_blanks(pos);
      f.push_back(read_number_field(text_, pos, file_, line_, line_start_));
      pos = skip_blanks(pos);
      const char want = k + 1 < kJointCount ? ',' : ']';
      if (pos >= text_.size() || text_[pos] != want)
        throw InputError(SourceLocation{file_, line_, column(pos), ""},
                         fmt::format("movej: expected '{}' after joint {}", want, k + 1));
      ++pos;
    }
    return f;
  }

  void add_joint_target(const NumberFields& f, size_t at) {
    PointSite site;
    site.fields = f;
    site.point.is_joint_target = true;
    site.point.line = line_;
    site.point.column = column(at);
    for (int k = 0; k < kJointCount; ++k) site.point.joints_deg[k] = rad2deg(f[k].value);
    out_.sites.push_back(std::move(site));
  }

  static Pose<double> pose_of(const NumberFields& f) {
    Pose<double> pose;
    pose.p << 1000 * f[0].value, 1000 * f[1].value, 1000 * f[2].value;  // m → mm
    const Eigen::Vector3d r(f[3].value, f[4].value, f[5].value);
    pose.R = r.norm() > 0 ? Eigen::AngleAxisd(r.norm(), r.normalized()).toRotationMatrix()
                          : Eigen::Matrix3d::Identity();
    return pose;
  }

  void add_target(const NumberFields& f, const std::string& name, size_t at) {
    PointSite site;
    site.fields = f;
    site.point.name = name;
    site.point.line = line_;
    site.point.column = column(at);
    site.point.base_T_tcp = pose_of(f);
    site.point.tool = tool_;
    out_.sites.push_back(std::move(site));
  }

  std::string_view text_;
  const std::string& file_;
  size_t at_ = 0;
  int line_ = 1;
  size_t line_start_ = 0;
  const ProgramFilterOptions& options_;
  std::string tool_;  ///< "" = the flange (no set_tcp yet)
  ProgramScan out_;
  /// A motion's use of a variable: the tool active there.
  struct Use {
    std::string tool;
    int line, column;
  };
  std::map<std::string, std::vector<size_t>> assignments_;  ///< sites by variable, text order
  std::unordered_map<size_t, std::vector<Use>> uses_;       ///< by site
  std::map<std::string, std::vector<Use>> later_uses_;      ///< before any assignment
};

}  // namespace

ProgramScan scan_urscript(std::string_view text, const std::string& file,
                          const ProgramFilterOptions& options) {
  return UrScanner(text, file, options).run();
}

}  // namespace robcal::detail
