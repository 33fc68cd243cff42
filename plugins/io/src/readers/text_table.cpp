#include "readers/text_table.h"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>

#include "plugslam/errors.h"
#include "images/image_file.h"

namespace plugslam {
namespace io {

std::vector<TextRow> dataRows(const std::string& text, const char* separators) {
  std::vector<TextRow> rows;
  std::size_t begin = 0;
  int line = 0;
  while (begin < text.size()) {
    std::size_t end = text.find('\n', begin);
    if (end == std::string::npos) end = text.size();
    ++line;
    TextRow row;
    row.line = line;
    std::size_t i = begin;
    while (i < end) {
      while (i < end && (std::strchr(separators, text[i]) || text[i] == '\r')) ++i;
      std::size_t j = i;
      while (j < end && !std::strchr(separators, text[j]) && text[j] != '\r') ++j;
      if (j > i) row.tokens.emplace_back(text, i, j - i);
      i = j;
    }
    if (!row.tokens.empty() && row.tokens.front()[0] != '#') rows.push_back(std::move(row));
    begin = end + 1;
  }
  return rows;
}

void requireColumns(const std::string& file, const TextRow& row, std::size_t n,
                    const char* layout) {
  if (row.tokens.size() < n)
    throw ParseError(file, row.line,
                     "expected " + std::to_string(n) + " columns (" + layout + "), got " +
                         std::to_string(row.tokens.size()));
}

namespace {
const std::string& rowToken(const std::string& file, const TextRow& row, std::size_t column,
                            const char* what) {
  if (column >= row.tokens.size())
    throw ParseError(file, row.line, std::string("missing ") + what);
  return row.tokens[column];
}
}  // namespace

double rowNumber(const std::string& file, const TextRow& row, std::size_t column,
                 const char* what) {
  const std::string& token = rowToken(file, row, column, what);
  char* end = nullptr;
  errno = 0;
  const double v = std::strtod(token.c_str(), &end);
  if (end == token.c_str() || *end != '\0' || !std::isfinite(v) || errno == ERANGE)
    throw ParseError(file, row.line,
                     std::string(what) + ": '" + token + "' is not a finite number");
  return v;
}

std::int64_t rowInteger(const std::string& file, const TextRow& row, std::size_t column,
                        const char* what) {
  const std::string& token = rowToken(file, row, column, what);
  char* end = nullptr;
  errno = 0;
  const long long v = std::strtoll(token.c_str(), &end, 10);
  bool ok = end != token.c_str() && errno != ERANGE;
  if (ok && *end == '.') {
    for (++end; *end == '0'; ++end) {
    }
  }
  if (!ok || *end != '\0')
    throw ParseError(file, row.line,
                     std::string(what) + ": '" + token + "' is not an integer");
  return static_cast<std::int64_t>(v);
}

std::string readTextFile(const std::string& path) {
  const std::vector<std::uint8_t> bytes = readFileBytes(path);
  return std::string(bytes.begin(), bytes.end());
}

}  // namespace io
}  // namespace plugslam
