#include "eval/text_file.h"

#include <cerrno>
#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>

#include "plugslam/errors.h"

namespace plugslam {
inline namespace abi_v1 {
namespace eval_detail {

std::vector<TextLine> readDataLines(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError("cannot open '" + path + "': " + std::strerror(errno));
  std::vector<TextLine> lines;
  std::string text;
  int number = 0;
  while (std::getline(in, text)) {
    ++number;
    for (char& c : text) {
      if (c == ',' || c == '\r') c = ' ';
    }
    std::istringstream ss(text);
    TextLine line;
    line.number = number;
    std::string token;
    while (ss >> token) line.tokens.push_back(token);
    if (line.tokens.empty() || line.tokens.front()[0] == '#') continue;
    lines.push_back(std::move(line));
  }
  if (in.bad()) throw InputError("error while reading '" + path + "'");
  return lines;
}

double parseNumber(const std::string& path, const TextLine& line, std::size_t column,
                   const char* what) {
  const std::string& token = line.tokens.at(column);
  const char* begin = token.c_str();
  char* end = nullptr;
  errno = 0;
  const double v = std::strtod(begin, &end);
  if (end == begin || *end != '\0') {
    throw ParseError(
        path, line.number,
        format("column %zu (%s): expected a number, got '%s'", column + 1, what, token.c_str()));
  }
  if (!std::isfinite(v)) {
    throw ParseError(path, line.number,
                     format("column %zu (%s): expected a finite number, got '%s'", column + 1, what,
                            token.c_str()));
  }
  return v;
}

std::string format(const char* fmt, ...) {
  va_list args;
  va_start(args, fmt);
  va_list copy;
  va_copy(copy, args);
  const int n = std::vsnprintf(nullptr, 0, fmt, copy);
  va_end(copy);
  std::string s(n > 0 ? static_cast<std::size_t>(n) : 0, '\0');
  if (n > 0) std::vsnprintf(s.data(), s.size() + 1, fmt, args);
  va_end(args);
  return s;
}

}  // namespace eval_detail
}  // namespace abi_v1
}  // namespace plugslam
