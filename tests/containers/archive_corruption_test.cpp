// Truncated, corrupted and crafted binary input must raise ParseError: never UB, a crash or a
// huge allocation.
#include <gtest/gtest.h>

#include <array>
#include <cstring>
#include <random>
#include <sstream>

#include "plugslam/archive.h"
#include "plugslam/property_container.h"

namespace plugslam {
namespace {

std::string encodeBinary(const PropertyContainer& c) {
  std::ostringstream ss;
  auto ar = makeOutArchive(ss, ArchiveFormat::kBinary);
  save(*ar, c);
  ar->finish();
  return ss.str();
}

void decodeBinary(const std::string& bytes) {
  std::istringstream in(bytes);
  auto ar = makeInArchive(in, ArchiveFormat::kBinary, "corrupt.bin");
  PropertyContainer c;
  load(*ar, c);
}

PropertyContainer sample() {
  PropertyContainer c;
  c.set<double>("x", 1.5);
  c.set<std::string>("name", "front");
  c.set<std::vector<Eigen::Vector2d>>("points", {{1, 2}, {3, 4}, {5, 6}});
  c.set<std::vector<std::string>>("labels", {"a", "bc"});
  c.emplace<PropertyContainer>("inner").set<std::int64_t>("n", -7);
  return c;
}

TEST(BinaryCorruption, EveryTruncationIsAParseError) {
  const std::string bytes = encodeBinary(sample());
  ASSERT_NO_THROW(decodeBinary(bytes));
  for (std::size_t n = 0; n < bytes.size(); ++n) {
    EXPECT_THROW(decodeBinary(bytes.substr(0, n)), ParseError) << "prefix of " << n << " bytes";
  }
}

TEST(BinaryCorruption, EveryFlippedByteIsAParseError) {
  const std::string bytes = encodeBinary(sample());
  for (std::size_t i = 0; i < bytes.size(); ++i) {
    for (unsigned char mask : {0x01, 0x80, 0xff}) {
      std::string bad = bytes;
      bad[i] = static_cast<char>(static_cast<unsigned char>(bad[i]) ^ mask);
      EXPECT_THROW(decodeBinary(bad), ParseError) << "byte " << i << " mask " << int(mask);
    }
  }
}

TEST(BinaryCorruption, ErrorsNameTheProblem) {
  try {
    decodeBinary("PLSB");
    FAIL();
  } catch (const ParseError& e) {
    EXPECT_EQ(e.file(), "corrupt.bin");
    EXPECT_NE(std::string(e.what()).find("truncated header"), std::string::npos) << e.what();
  }
  try {
    decodeBinary("hello world, this is not an archive");
    FAIL();
  } catch (const ParseError& e) {
    EXPECT_NE(std::string(e.what()).find("not a plugslam binary archive"), std::string::npos);
  }
  std::string bytes = encodeBinary(sample());
  bytes[4] = 9;  // format version
  try {
    decodeBinary(bytes);
    FAIL();
  } catch (const ParseError& e) {
    EXPECT_NE(std::string(e.what()).find("format version 9"), std::string::npos) << e.what();
  }
}

// ---- crafted payloads with a valid header and checksum --------------------------------------

std::uint32_t crc32(const std::string& s) {
  std::uint32_t c = 0xffffffffu;
  for (unsigned char ch : s) {
    c ^= ch;
    for (int k = 0; k < 8; ++k) c = (c & 1) ? 0xEDB88320u ^ (c >> 1) : c >> 1;
  }
  return ~c;
}

void putLE(std::string& s, std::uint64_t v, int bytes) {
  for (int i = 0; i < bytes; ++i) s.push_back(static_cast<char>((v >> (8 * i)) & 0xff));
}

std::string withHeader(const std::string& payload, std::uint64_t length) {
  std::string s = "PLSB";
  putLE(s, 1, 4);
  putLE(s, length, 8);
  putLE(s, crc32(payload), 4);
  return s + payload;
}

std::string withHeader(const std::string& payload) { return withHeader(payload, payload.size()); }

std::string varint(std::uint64_t v) {
  std::string s;
  while (v >= 0x80) {
    s.push_back(static_cast<char>((v & 0x7f) | 0x80));
    v >>= 7;
  }
  s.push_back(static_cast<char>(v));
  return s;
}

TEST(BinaryCorruption, TheHeaderMatchesOurCrcAndLayout) {
  // Guards the crafted tests below: a hand-built archive of one double must load.
  std::string payload(1, '\x05');
  putLE(payload, 0x3ff8000000000000ull, 8);  // 1.5
  std::istringstream in(withHeader(payload));
  auto ar = makeInArchive(in, ArchiveFormat::kBinary);
  EXPECT_EQ(ar->readDouble(), 1.5);
}

TEST(BinaryCorruption, HugeAnnouncedLengthDoesNotAllocate) {
  std::string payload(1, '\x01');
  EXPECT_THROW(decodeBinary(withHeader(payload, std::uint64_t{1} << 62)), ParseError);
}

TEST(BinaryCorruption, CraftedCountsAreCheckedAgainstTheInput) {
  const std::string huge = varint(std::uint64_t{1} << 60);
  EXPECT_THROW(decodeBinary(withHeader("\x07" + huge)), ParseError);  // doubles blob
  EXPECT_THROW(decodeBinary(withHeader("\x06" + huge)), ParseError);  // string
  EXPECT_THROW(decodeBinary(withHeader("\x08" + huge)), ParseError);  // array
  EXPECT_THROW(decodeBinary(withHeader(std::string("\x09\xff\xff\xff\xff", 5))), ParseError);
  EXPECT_THROW(decodeBinary(withHeader(std::string(11, '\xff'))), ParseError);           // bad tag
  EXPECT_THROW(decodeBinary(withHeader("\x04" + std::string(11, '\xff'))), ParseError);  // varint
  EXPECT_THROW(decodeBinary(withHeader(std::string("\x01\x01", 2))), ParseError);        // trailing
  EXPECT_THROW(decodeBinary(withHeader("")), ParseError);                                // no value
}

TEST(BinaryCorruption, DeepNestingIsRefusedWithoutExhaustingTheStack) {
  std::string payload;
  for (int i = 0; i < 100000; ++i) payload += "\x08\x01";  // arrays of one array of ...
  payload += "\x01";
  EXPECT_THROW(decodeBinary(withHeader(payload)), ParseError);
}

TEST(BinaryCorruption, WrongValueTypeNamesTheField) {
  // {"x": {"type": "double", "value": "oops"}}: structurally valid, semantically wrong.
  auto str = [](const std::string& s) { return "\x06" + varint(s.size()) + s; };
  auto key = [](const std::string& s) { return varint(s.size()) + s; };
  std::string inner = std::string("\x09\x02\x00\x00\x00", 5) + key("type") + str("double") +
                      key("value") + str("oops");
  std::string payload = std::string("\x09\x01\x00\x00\x00", 5) + key("x") + inner;
  try {
    decodeBinary(withHeader(payload));
    FAIL();
  } catch (const ParseError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("'x.value'"), std::string::npos) << msg;
    EXPECT_NE(msg.find("expected a double, found a string"), std::string::npos) << msg;
  }
}

// Mutations behind a recomputed checksum reach the structural parser and the loaders: each must
// load or raise ParseError, nothing else (the sanitizer build checks there is no UB either).
TEST(BinaryCorruption, RandomMutationsWithValidChecksum) {
  const std::string bytes = encodeBinary(sample());
  const std::string payload = bytes.substr(20);
  std::mt19937 rng(1234);
  int loaded = 0, refused = 0;
  for (int round = 0; round < 3000; ++round) {
    std::string p = payload;
    const int edits = 1 + static_cast<int>(rng() % 4);
    for (int e = 0; e < edits; ++e) {
      const std::size_t at = rng() % p.size();
      switch (rng() % 3) {
        case 0:
          p[at] = static_cast<char>(rng() & 0xff);
          break;
        case 1:
          p.erase(at, 1 + rng() % 8);
          break;
        default:
          p.insert(at, 1, static_cast<char>(rng() & 0xff));
          break;
      }
      if (p.empty()) p = "\x01";
    }
    try {
      decodeBinary(withHeader(p));
      ++loaded;
    } catch (const ParseError&) {
      ++refused;
    }
  }
  EXPECT_GT(refused, 0);
  EXPECT_EQ(loaded + refused, 3000);
}

}  // namespace
}  // namespace plugslam
