#include "robcal/programs/frames_file.hpp"

#include <fmt/format.h>

#include <Eigen/Geometry>
#include <charconv>
#include <cmath>

#include "../io/csv_fields.hpp"
#include "program_scan.hpp"
#include "robcal/core/error.hpp"
#include "robcal/io/atomic_file.hpp"

namespace robcal {

FramesFile read_frames_file(const std::string& path) {
  const std::string text = read_text_file(path);
  FramesFile out;
  bool header = true;
  int line_number = 0;
  size_t at = 0;
  while (at < text.size()) {
    ++line_number;
    size_t end = text.find('\n', at);
    if (end == std::string::npos) end = text.size();
    std::string_view line(text.data() + at, end - at);
    at = end + 1;
    if (line_number == 1 && line.starts_with("\xEF\xBB\xBF")) line.remove_prefix(3);  // BOM
    if (csv::trim(line).empty() || csv::trim(line).front() == '#') continue;
    std::vector<int> columns;
    const std::vector<std::string_view> f = csv::split_fields(line, &columns);
    const auto fail = [&](size_t field, const std::string& what) {
      throw InputError(SourceLocation{path, line_number, columns[field], ""}, what);
    };
    if (header) {
      static const char* const kColumns[] = {"kind", "name", "x", "y", "z", "qw", "qx", "qy", "qz"};
      if (f.size() != 9) fail(0, "expected the header kind,name,x,y,z,qw,qx,qy,qz");
      for (size_t k = 0; k < 9; ++k)
        if (f[k] != kColumns[k])
          fail(k, fmt::format("expected column '{}', found '{}' (header kind,name,x,y,z,qw,qx,qy,"
                              "qz)",
                              kColumns[k], f[k]));
      header = false;
      continue;
    }
    if (f.size() != 9) fail(0, fmt::format("expected 9 fields, found {}", f.size()));
    if (f[0] != "tool" && f[0] != "frame")
      fail(0, fmt::format("expected kind tool or frame, found '{}'", f[0]));
    if (f[1].empty()) fail(1, "empty name");
    double v[7];
    for (size_t k = 0; k < 7; ++k) {
      const std::string_view cell = f[k + 2];
      const auto [ptr, ec] = std::from_chars(cell.data(), cell.data() + cell.size(), v[k]);
      if (cell.empty() || ec != std::errc() || ptr != cell.data() + cell.size() ||
          !std::isfinite(v[k]))
        fail(k + 2, fmt::format("expected a finite number, found '{}'", cell));
    }
    // A tool or work object 100 m away is a unit slip (µm, or metres typed twice), not a cell.
    constexpr double kMaxMm = 100000;
    for (size_t k = 0; k < 3; ++k)
      if (std::abs(v[k]) > kMaxMm)
        fail(k + 2, fmt::format("{} mm is outside the plausible range [-{}, {}] mm", f[k + 2],
                                kMaxMm, kMaxMm));
    const Eigen::Quaterniond q(v[3], v[4], v[5], v[6]);
    if (std::abs(q.norm() - 1) > 1e-3)
      fail(5, fmt::format("quaternion norm {:.6f}: expected a unit quaternion", q.norm()));
    Pose<double> pose;
    pose.p << v[0], v[1], v[2];
    pose.R = q.normalized().toRotationMatrix();
    auto& map = f[0] == "tool" ? out.tools : out.frames;
    if (!map.emplace(detail::upper(f[1]), pose).second)
      fail(1, fmt::format("{} '{}' given twice", f[0], f[1]));
  }
  if (header) throw InputError(SourceLocation{path, 0, 0, ""}, "empty frames file");
  return out;
}

}  // namespace robcal
