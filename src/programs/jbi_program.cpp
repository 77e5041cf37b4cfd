// Yaskawa INFORM job (.jbi): measurement programs and their joint positions read back.
//
// Grammar constraints relied on (what the controller's job loader checks):
// - `/JOB`, `//NAME name` (at most 8 characters on the older controllers, upper case),
//   `//POS`, `///NPOS c,bc,ec,p,bp,ex` whose first count equals the number of C variables
//   defined below, `///TOOL n`, `///POSTYPE PULSE`, `///PULSE`, then `Cnnnnn=p1,...,p6`
//   numbered from C00000 without gaps, then `//INST`, `///DATE yyyy/mm/dd hh:mm`,
//   `///ATTR SC,RW`, `///GROUP1 RB1`, `NOP`, the instructions, `END`;
// - joints are integer encoder pulses (pulses per degree from the robot's parameters), so a
//   configuration comes back to within half a pulse, exactly the rounded pulse count;
// - comments are lines starting with `'`, at most 32 characters;
// - MOVJ C..... VJ=speed% with PL=0 stops exactly (fine point); TIMER T=seconds waits.

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <map>
#include <numeric>
#include <optional>

#include "measurement_writers.hpp"
#include "program_scan.hpp"
#include "robcal/core/error.hpp"
#include "robcal/kinematics/orientation.hpp"

namespace robcal::detail {

std::string write_jbi_measurement(const MeasurementPart& part) {
  const MeasurementProgramRequest& r = part.request;
  const std::array<double, kJointCount>& ppd = *r.pulses_per_degree;
  std::string pulses;
  std::string inst;
  int c = 0;
  const auto move = [&](const Vector6d& q) {
    pulses += fmt::format("C{:05d}=", c);
    for (int j = 0; j < kJointCount; ++j) {
      const double p = std::round(q[j] * ppd[static_cast<size_t>(j)]);
      if (std::abs(p) > 2e9)
        throw InputError(
            SourceLocation{"", 0, 0, "--pulses-per-degree"},
            fmt::format("joint {} at {} deg is {} pulses: beyond a 32-bit count", j + 1, q[j], p));
      pulses += fmt::format("{}{:.0f}", j == 0 ? "" : ",", p);
    }
    pulses += "\n";
    inst += fmt::format("MOVJ C{:05d} VJ={:.2f} PL=0\n", c++, r.joint_speed_percent);
  };
  for (const Visit& v : part.visits) {
    inst += fmt::format("'{}\n", v.label());
    if (v.approach) move(v.approach_deg);
    move(v.target_deg);
    if (!v.measure) continue;
    inst += fmt::format("TIMER T={:.2f}\n", r.settle_s);
    if (r.hook == MeasurementHook::WaitInput)
      inst += fmt::format("WAIT IN#({})=ON\n", r.signal);
    else
      inst += fmt::format("PULSE OT#({}) T=0.50\n", r.signal);
  }
  return fmt::format(
      "/JOB\n//NAME {}\n//POS\n///NPOS {},0,0,0,0,0\n///TOOL {}\n///POSTYPE PULSE\n///PULSE\n"
      "{}//INST\n///DATE {}\n///ATTR SC,RW\n///GROUP1 RB1\nNOP\n{}END\n",
      part.program, c, r.tool_number, pulses, r.date, inst);
}

std::vector<JointMove> read_jbi_joint_moves(const std::string& text, const std::string& file,
                                            const std::array<double, kJointCount>& ppd) {
  // The //POS section as the filter reads it: ///NPOS counts, position names and values.
  (void)scan_jbi(text, file, ProgramFilterOptions{});
  std::map<int, Vector6d> positions;
  std::vector<std::pair<int, int>> order;  // (C index, line)
  bool in_pulse = false, in_inst = false;
  size_t at = 0;
  int number = 0;
  while (at < text.size()) {
    ++number;
    const size_t start = at;
    size_t end = text.find('\n', at);
    if (end == std::string::npos) end = text.size();
    std::string_view line(text.data() + start, end - start);
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    at = end + 1;
    const auto fail = [&](size_t column, const std::string& what) {
      throw InputError(SourceLocation{file, number, static_cast<int>(column) + 1, ""}, what);
    };
    // `Cnnnnn` at `pos`: the index.
    const auto c_index = [&](size_t pos) {
      size_t offset = start + pos + 1;
      const double index = read_number(text, offset, file, number, start);
      if (index != std::floor(index) || index < 0 || index > 99999)
        fail(pos, "expected a C variable C00000..C99999");
      return std::pair{static_cast<int>(index), offset - start};
    };
    if (line.starts_with("///PULSE")) {
      in_pulse = true;
    } else if (line.starts_with("//INST")) {
      in_pulse = false;
      in_inst = true;
    } else if (line.starts_with("///RCONF") || line.starts_with("///TOOL") ||
               line.starts_with("///POSTYPE") || line.starts_with("///USER")) {
      if (line.starts_with("///POSTYPE") && line.find("PULSE") == std::string_view::npos)
        fail(11, "only ///POSTYPE PULSE positions are read");
    } else if (in_pulse && line.starts_with("C")) {
      const auto [index, after] = c_index(0);
      if (after >= line.size() || line[after] != '=') fail(after, "expected '='");
      Vector6d q;
      size_t offset = start + after + 1;
      for (int j = 0; j < kJointCount; ++j) {
        if (j > 0) {
          if (offset - start >= line.size() || line[offset - start] != ',')
            fail(offset - start, fmt::format("expected ',' and the pulses of axis {}", j + 1));
          ++offset;
        }
        q[j] = read_number(text, offset, file, number, start) / ppd[static_cast<size_t>(j)];
      }
      if (!positions.emplace(index, q).second) fail(0, fmt::format("C{:05d} defined twice", index));
    } else if (in_inst && line.starts_with("MOVJ C")) {
      order.emplace_back(c_index(5).first, number);
    }
  }
  std::vector<JointMove> moves;
  for (const auto& [index, line] : order) {
    const auto it = positions.find(index);
    if (it == positions.end())
      throw InputError(SourceLocation{file, line, 6, ""},
                       fmt::format("C{:05d} is not defined in //POS", index));
    moves.push_back({it->second, line});
  }
  return moves;
}

}  // namespace robcal::detail

// JBI filtering. The //POS section is a list of pseudo-instructions, each setting a state for the
// positions after it, and positions (NX100/DX100 "Job Data Format"):
// - `///NPOS c,bc,ec,p,bp,ex`: the counts of robot (C), base-axis (BC) and station-axis (EC)
//   teaching positions, then of robot (P), base-axis (BP) and station-axis (EX) position
//   variables; the loader refuses a job whose counts differ from the positions defined
//   (checked here for all six, the message naming the count; a name defined twice is refused,
//   so equal counts mean as many distinct names). The filter changes numbers only, never a
//   name or a line, so the counts it writes are the ones it read;
// - `///USER n` (user frame 0..63), `///TOOL n` (tool 0..63);
// - `///POSTYPE PULSE|BASE|ROBOT|USER|TOOL|MTOOL` and `///PULSE` or `///RECTAN`: the positions
//   after are encoder pulses or Cartesian;
// - `///RCONF l,m,n,o,p,q[,...]`: the configuration of the Cartesian positions after it:
//   l 0 flip / 1 no-flip, m 0 upper / 1 lower arm, n 0 front / 1 rear, o, p, q: R, T, S (axes
//   4, 6, 1) below 180° (0) or at or beyond it (1); further values are unused;
// - `Cnnnnn=j1,...,j6` (pulses) or `Cnnnnn=X,Y,Z,Rx,Ry,Rz` (mm, degrees; R = Rz·Ry·Rx, the
//   angles about the fixed x, y, z axes); `BCnnnnn=`/`ECnnnnn=` are the base and station axes,
//   not the arm: kept as written.
// Targets: C positions in pulses (joint targets: pulses / pulses-per-degree of the robot
// file, written back as whole pulses) and Cartesian ones in the ROBOT or BASE frame (the same
// frame for a robot without a base axis: with BC positions in the job, BASE is refused) or in
// user frame n (frames file name USER[n]), with tool n (TOOL[n]; without a ///TOOL line, the
// corrector's default tool). RCONF is kept: a correction that needs another is refused.
// Positions are written with 3 decimals of a mm and 4 of a degree, the controller's own
// resolution; lines end as written (CR LF or LF).
namespace robcal::detail {
namespace {

class JbiScanner {
 public:
  JbiScanner(std::string_view text, const std::string& file, const ProgramFilterOptions& options)
      : text_(text), file_(file), options_(options) {}

  ProgramScan run() {
    size_t at = 0;
    bool in_pos = false;
    while (at < text_.size()) {
      ++line_;
      line_start_ = at;
      size_t end = text_.find('\n', at);
      if (end == std::string_view::npos) end = text_.size();
      std::string_view line = text_.substr(at, end - at);
      if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
      at = end + 1;
      if (line.starts_with("//POS")) {
        in_pos = true;
      } else if (line.starts_with("//INST")) {
        break;  // instructions: no position data after this
      } else if (in_pos) {
        pos_line(line);
      }
    }
    if (base_frame_line_ && defined_[1] > 0)
      throw InputError(SourceLocation{file_, *base_frame_line_, 1, ""},
                       "Cartesian position in the BASE frame of a robot on a base axis (the job "
                       "has BC positions): the frame moves, the position is not corrected");
    if (npos_line_ == 0 && std::accumulate(defined_.begin(), defined_.end(), 0) > 0)
      throw InputError(SourceLocation{file_, 0, 0, "///NPOS"},
                       "the job defines positions but has no ///NPOS line in //POS");
    for (size_t k = 0; k < kKinds.size(); ++k)
      if (npos_line_ > 0 && declared_[k] != defined_[k])
        throw InputError(SourceLocation{file_, npos_line_, 9, "///NPOS"},
                         fmt::format("///NPOS declares {} {} positions (count {} of c,bc,ec,p,bp,"
                                     "ex), the job defines {}",
                                     declared_[k], kKinds[k], k + 1, defined_[k]));
    return std::move(out_);
  }

 private:
  /// The six ///NPOS counts in order: robot, base-axis and station-axis teaching positions,
  /// then robot, base-axis and station-axis position variables.
  static constexpr std::array<const char*, 6> kKinds = {"C", "BC", "EC", "P", "BP", "EX"};

  [[noreturn]] void fail(size_t column, const std::string& what) const {
    throw InputError(SourceLocation{file_, line_, static_cast<int>(column) + 1, ""}, what);
  }

  // Comma-separated numbers from `column` to the end of the line, with their byte ranges.
  std::vector<NumberField> numbers(std::string_view line, size_t column) const {
    std::vector<NumberField> out;
    size_t offset = line_start_ + column;
    const size_t end = line_start_ + line.size();
    for (;;) {
      out.push_back(read_number_field(text_, offset, file_, line_, line_start_));
      if (offset >= end) return out;
      if (text_[offset] != ',') fail(offset - line_start_, "expected ',' between the values");
      ++offset;
    }
  }

  int integer_after(std::string_view line, size_t column, int lowest, int highest) const {
    const std::vector<NumberField> n = numbers(line, column);
    if (n.size() != 1 || n[0].value != std::floor(n[0].value) || n[0].value < lowest ||
        n[0].value > highest)
      fail(column, fmt::format("expected one whole number {} to {}", lowest, highest));
    return static_cast<int>(n[0].value);
  }

  void pos_line(std::string_view line) {
    if (line.empty()) return;
    if (line.starts_with("///NPOS ")) {
      if (npos_line_ > 0)
        fail(0, fmt::format("second ///NPOS line (the first at line {})", npos_line_));
      const std::vector<NumberField> n = numbers(line, 8);
      if (n.size() != 6) fail(8, "///NPOS: expected six counts c,bc,ec,p,bp,ex");
      for (size_t k = 0; k < 6; ++k) {
        // As many as the names allow: C/BC/EC00000..99999 (five digits), P/BP/EX0000..9999.
        const int most = k < 3 ? 100000 : 10000;
        if (n[k].value != std::floor(n[k].value) || n[k].value < 0 || n[k].value > most)
          fail(n[k].begin - line_start_,
               fmt::format("///NPOS: expected a whole {} count 0..{} (the {} names have {} "
                           "digits)",
                           kKinds[k], most, kKinds[k], k < 3 ? 5 : 4));
        declared_[k] = static_cast<int>(n[k].value);
      }
      npos_line_ = line_;
    } else if (line.starts_with("///USER ")) {
      user_ = integer_after(line, 8, 0, 63);
    } else if (line.starts_with("///TOOL ")) {
      tool_ = integer_after(line, 8, 0, 63);
    } else if (line.starts_with("///POSTYPE ")) {
      postype_ = std::string(line.substr(11));
      static const char* const kTypes[] = {"PULSE", "BASE", "ROBOT", "USER", "TOOL", "MTOOL"};
      if (std::find(std::begin(kTypes), std::end(kTypes), postype_) == std::end(kTypes))
        fail(11, fmt::format("unknown position type '{}': expected PULSE, BASE, ROBOT, USER, "
                             "TOOL or MTOOL",
                             postype_));
    } else if (line == "///PULSE") {
      rectan_ = false;
    } else if (line == "///RECTAN") {
      rectan_ = true;
    } else if (line.starts_with("///RCONF ")) {
      const std::vector<NumberField> n = numbers(line, 9);
      if (n.size() < 6) fail(9, "///RCONF: expected at least six flags l,m,n,o,p,q");
      rconf_.clear();
      for (const NumberField& f : n) {
        if (f.value != 0 && f.value != 1)
          fail(f.begin - line_start_, "///RCONF: expected flags 0 or 1");
        if (rconf_.size() < 6) rconf_.push_back(static_cast<int>(f.value));
      }
    } else if (line.starts_with("///")) {
      // Other header pseudo-instructions (///COMM, ///ATTR ...) carry no position state.
    } else if (line.starts_with("BC") || line.starts_with("EC")) {
      position_name(line, line[0] == 'B' ? 1 : 2, 2);  // checked, kept as written
    } else if (line.starts_with("BP") || line.starts_with("EX")) {
      // Variables: their stored values, kept as written.
      position_name(line, line[0] == 'B' ? 4 : 5, 2);
    } else if (line.starts_with("P")) {
      position_name(line, 3, 1);
    } else if (line.starts_with("C")) {
      position(line);
    } else {
      fail(0,
           "expected a ///pseudo-instruction, a C, BC or EC position or a P, BP or EX "
           "variable in //POS");
    }
  }

  // `Cnnnnn=` / `BCnnnnn=` / `ECnnnnn=` (five digits), `Pnnnn=` / `BPnnnn=` / `EXnnnn=`
  // (variables, up to four) of kind `kind` (kKinds): the name, checked and counted for
  // ///NPOS; the values start after it. A name defined twice is refused: the job would hold
  // two values for one position (and the counts could still agree).
  std::string position_name(std::string_view line, size_t kind, size_t digits_at) {
    const size_t digits = kind < 3 ? 5 : 4;
    size_t k = digits_at;
    while (k < line.size() && std::isdigit(static_cast<unsigned char>(line[k]))) ++k;
    const bool ok = digits == 5 ? k - digits_at == 5 : (k > digits_at && k - digits_at <= digits);
    if (!ok || k >= line.size() || line[k] != '=')
      fail(digits_at, digits == 5 ? "expected a position name with five digits and '=' (C00000=...)"
                                  : "expected a position variable name with up to four digits "
                                    "and '=' (P0001=...)");
    int index = 0;
    std::from_chars(line.data() + digits_at, line.data() + k, index);
    std::vector<int>& first_line = defined_at_[kind];
    if (first_line.empty()) first_line.assign(digits == 5 ? 100000 : 10000, 0);
    std::string name(line.substr(0, k));
    if (first_line[static_cast<size_t>(index)] > 0)
      fail(0, fmt::format("{} is defined twice (first at line {})", name,
                          first_line[static_cast<size_t>(index)]));
    first_line[static_cast<size_t>(index)] = line_;
    ++defined_[kind];
    return name;
  }

  void position(std::string_view line) {
    const std::string name = position_name(line, 0, 1);
    const size_t values_at = name.size() + 1;
    const std::vector<NumberField> f = numbers(line, values_at);
    // A 7-axis arm (SIA, SDA) has seven robot values; its positions cannot be corrected with a
    // six-axis model, and keeping some positions of a job corrected and others not would mislead.
    if (f.size() == 7)
      fail(values_at, fmt::format("{} has seven robot axis values: a seven-axis arm (SIA/SDA "
                                  "series); robcal calibrates six-axis arms, the job is refused",
                                  name));
    if (f.size() != kJointCount)
      fail(values_at, fmt::format("{}: expected six robot axis values, found {}", name, f.size()));
    PointSite site;
    site.point.name = name;
    site.point.line = line_;
    site.point.column = static_cast<int>(values_at) + 1;
    site.fields = f;
    if (!rectan_) {
      if (postype_ != "PULSE") fail(0, "pulse data after ///POSTYPE " + postype_);
      if (!options_.joints) return;
      if (options_.pulses_per_degree[0] <= 0)
        fail(values_at,
             "pulse positions need the robot's pulses per degree (robot file key "
             "pulses_per_degree)");
      site.point.is_joint_target = true;
      for (int j = 0; j < kJointCount; ++j)
        site.point.joints_deg[j] = f[j].value / options_.pulses_per_degree[static_cast<size_t>(j)];
      out_.sites.push_back(std::move(site));
      return;
    }
    if (postype_ == "TOOL" || postype_ == "MTOOL" || postype_ == "PULSE" || postype_.empty())
      fail(0, fmt::format("Cartesian position of type '{}': expected ROBOT, BASE or USER",
                          postype_.empty() ? "none" : postype_));
    if (postype_ == "BASE" && !base_frame_line_) base_frame_line_ = line_;
    if (postype_ == "USER") {
      if (!user_) fail(0, "///POSTYPE USER without a ///USER line before it");
      site.point.frame = fmt::format("USER[{}]", *user_);
    }
    if (rconf_.empty()) fail(0, "Cartesian position without a ///RCONF line before it");
    site.point.config = rconf_;
    if (tool_) site.point.tool = fmt::format("TOOL[{}]", *tool_);
    site.point.base_T_tcp.p << f[0].value, f[1].value, f[2].value;
    site.point.base_T_tcp.R = rotation_from_euler_deg(
        Eigen::Vector3d(f[5].value, f[4].value, f[3].value), EulerConvention::ZyxABC);
    out_.sites.push_back(std::move(site));
  }

  std::string_view text_;
  const std::string& file_;
  const ProgramFilterOptions& options_;
  int line_ = 0;
  size_t line_start_ = 0;
  int npos_line_ = 0;
  std::array<int, 6> declared_{}, defined_{};
  /// By kind (kKinds) and position number: the line defining it (0: none yet).
  std::array<std::vector<int>, 6> defined_at_;
  std::optional<int> user_, tool_, base_frame_line_;
  std::string postype_;
  bool rectan_ = false;
  std::vector<int> rconf_;
  ProgramScan out_;
};

}  // namespace

ProgramScan scan_jbi(std::string_view text, const std::string& file,
                     const ProgramFilterOptions& options) {
  return JbiScanner(text, file, options).run();
}

}  // namespace robcal::detail
