#include "f2c/io/correspondences.h"

#include <fmt/format.h>

#include "f2c/util/error.h"
#include "f2c/util/file.h"
#include "f2c/util/text.h"

namespace f2c {
namespace fs = std::filesystem;

void WriteCorrespondences(const fs::path& path, const std::vector<Correspondence>& cs) {
  std::string text = fmt::format("n_correspondences {}\n", cs.size());
  for (const Correspondence& c : cs) {
    text += fmt::format("point3d SCAN:{} SCAN:{} {:.6f} {:.6f} {:.6f} {:.6f} {:.6f} {:.6f}\n", c.frame_a, c.frame_b,
                        c.point_in_a.x(), c.point_in_a.y(), c.point_in_a.z(), c.point_in_b.x(), c.point_in_b.y(),
                        c.point_in_b.z());
  }
  WriteFileAtomic(path, text);
}

std::vector<Correspondence> ReadCorrespondences(const fs::path& path) {
  const auto lines = ReadDataLines(path);
  if (lines.empty()) ThrowInputError(path, "empty correspondence file");
  const auto header = SplitWhitespace(lines[0].text);
  long n = 0;
  if (header.size() != 2 || header[0] != "n_correspondences" || !ParseInt(header[1], &n) || n < 0) {
    ThrowInputError(path, lines[0].number, "expected 'n_correspondences N'");
  }
  std::vector<Correspondence> out;
  for (size_t i = 1; i < lines.size(); ++i) {
    const auto t = SplitWhitespace(lines[i].text);
    long a = 0, b = 0;
    if (t.size() != 9 || t[0] != "point3d" || t[1].rfind("SCAN:", 0) != 0 || t[2].rfind("SCAN:", 0) != 0 ||
        !ParseInt(t[1].substr(5), &a) || !ParseInt(t[2].substr(5), &b)) {
      ThrowInputError(path, lines[i].number, "expected 'point3d SCAN:<a> SCAN:<b> xA yA zA xB yB zB'");
    }
    const auto v = ParseDoublesOrThrow(t, 3, path, lines[i].number, "6 coordinates");
    out.push_back({static_cast<int>(a), static_cast<int>(b), {v[0], v[1], v[2]}, {v[3], v[4], v[5]}});
  }
  if (static_cast<long>(out.size()) != n) {
    ThrowInputError(path, fmt::format("n_correspondences says {} but {} lines follow", n, out.size()));
  }
  return out;
}

}  // namespace f2c
