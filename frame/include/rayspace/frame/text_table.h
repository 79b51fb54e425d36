// Plain-text tables for the terminal: each column as wide as its widest cell.
#pragma once
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

namespace rayspace::app {

using Cells = std::vector<std::string>;

// Prints the header and the rows, two spaces between columns; columns whose `right` entry is true are
// right-aligned. A row with fewer cells than the header ends with its last cell as it is (a note
// spanning the remaining columns).
void PrintColumns(std::FILE* out, const Cells& header, const std::vector<Cells>& rows, const std::vector<bool>& right);

// 1234567 -> "1,234,567".
std::string Thousands(std::uint64_t n);

}  // namespace rayspace::app
