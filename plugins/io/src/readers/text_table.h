#pragma once
// Whitespace- or comma-separated text tables of camera datasets (KITTI calib.txt and times.txt,
// EuRoC data.csv, TUM lists): data rows with their line numbers, and strict number parsing that
// names the file, line and column.
#include <cstdint>
#include <string>
#include <vector>

namespace plugslam {
namespace io {

/// One data row: its 1-based line number and its tokens.
struct TextRow {
  int line = 0;                     ///< 1-based line number in the file
  std::vector<std::string> tokens;  ///< the row split at the separators, empty tokens dropped
};

/// The rows of `text` that are neither empty nor comments (first non-blank character '#').
/// `separators` split a row into tokens; "\r" at line ends is ignored.
std::vector<TextRow> dataRows(const std::string& text, const char* separators = " \t,");

/// Token `column` of `row` as a finite double; ParseError(file, line) saying what was expected.
double rowNumber(const std::string& file, const TextRow& row, std::size_t column,
                 const char* what);
/// Token `column` of `row` as an integer (digits with an optional sign and an optional all-zero
/// fraction, as EuRoC writes "1403715274312143104.0000000000"); ParseError otherwise.
std::int64_t rowInteger(const std::string& file, const TextRow& row, std::size_t column,
                        const char* what);
/// ParseError(file, row.line) unless the row has at least `n` tokens.
void requireColumns(const std::string& file, const TextRow& row, std::size_t n,
                    const char* layout);

/// The whole of a text file; InputError naming it when it is missing or unreadable.
std::string readTextFile(const std::string& path);

}  // namespace io
}  // namespace plugslam
