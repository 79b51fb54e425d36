#include "rayspace/frame/text_table.h"

#include <algorithm>

namespace rayspace::app {
namespace {

void PrintRow(std::FILE* out, const Cells& row, const std::vector<std::size_t>& width, const std::vector<bool>& right) {
  std::string line;
  for (std::size_t c = 0; c < row.size(); ++c) {
    const bool spans = c + 1 == row.size() && row.size() < width.size();
    const std::string pad(spans ? 0 : width[c] - std::min(width[c], row[c].size()), ' ');
    line += (c ? "  " : "") + (right[c] && !spans ? pad + row[c] : row[c] + (c + 1 < row.size() ? pad : ""));
  }
  std::fprintf(out, "%s\n", line.c_str());
}

}  // namespace

void PrintColumns(std::FILE* out, const Cells& header, const std::vector<Cells>& rows, const std::vector<bool>& right) {
  std::vector<std::size_t> width(header.size());
  for (std::size_t c = 0; c < header.size(); ++c) width[c] = header[c].size();
  for (const Cells& row : rows)
    for (std::size_t c = 0; c < row.size(); ++c)
      if (c + 1 < row.size() || row.size() == header.size()) width[c] = std::max(width[c], row[c].size());
  PrintRow(out, header, width, right);
  for (const Cells& row : rows) PrintRow(out, row, width, right);
}

std::string Thousands(std::uint64_t n) {
  std::string digits = std::to_string(n), out;
  for (std::size_t i = 0; i < digits.size(); ++i) {
    if (i && (digits.size() - i) % 3 == 0) out += ',';
    out += digits[i];
  }
  return out;
}

}  // namespace rayspace::app
