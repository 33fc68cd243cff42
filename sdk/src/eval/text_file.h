#pragma once
// Line-oriented reading of numeric text files, shared by the eval readers.
#include <string>
#include <vector>

namespace plugslam {
inline namespace abi_v1 {
namespace eval_detail {

/// One data line of a text file: its 1-based number and its whitespace-separated tokens.
struct TextLine {
  int number = 0;
  std::vector<std::string> tokens;
};

/// Reads every non-empty line that does not start with '#' (commas count as spaces); throws
/// InputError if the file cannot be opened.
std::vector<TextLine> readDataLines(const std::string& path);

/// Parses a token as a finite double; throws ParseError(path, line, ...) naming the column.
double parseNumber(const std::string& path, const TextLine& line, std::size_t column,
                   const char* what);

/// printf-style formatting into a std::string.
std::string format(const char* fmt, ...) __attribute__((format(printf, 1, 2)));

}  // namespace eval_detail
}  // namespace abi_v1
}  // namespace plugslam
