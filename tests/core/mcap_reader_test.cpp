// The MCAP reader on files of the SDK's own writer (the ROS 2 bags of @mcap/core are read in
// plugins/io/tests/ros2_bags_test.cpp): indexed and scanned reads agree, chunks uncompressed, lz4
// and zstd, the topic filter skips chunks, and every damaged file (cut anywhere, any byte
// flipped, a bad CRC, a chunk that does not decompress) is a ParseError naming the file and the
// offset, or a warning and the messages before the damage; never a crash.
#include <gtest/gtest.h>
#include <lz4frame.h>
#include <zstd.h>

#include <fstream>
#include <iterator>

#include "plugslam/errors.h"
#include "plugslam/mcap/reader.h"
#include "plugslam/mcap/records.h"
#include "plugslam/mcap/writer.h"
#include "temp_dir.h"

namespace plugslam::mcap {
namespace {

std::string lz4(const std::string& in) {
  std::string out(LZ4F_compressFrameBound(in.size(), nullptr), '\0');
  const size_t n = LZ4F_compressFrame(out.data(), out.size(), in.data(), in.size(), nullptr);
  out.resize(n);
  return out;
}

std::string zstd(const std::string& in) {
  std::string out(ZSTD_compressBound(in.size()), '\0');
  out.resize(ZSTD_compress(out.data(), out.size(), in.data(), in.size(), 3));
  return out;
}

std::string slurp(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(f), {}};
}

// A file of two topics: 40 messages on /a, then 40 on /b, in chunks of ~1 kB.
std::string makeFile(const plugslam::testing::TempDir& dir, const std::string& compression) {
  WriterOptions o;
  o.profile = "ros2";
  o.chunk_size = 1024;
  o.compression = compression;
  if (compression == "lz4") o.compress = lz4;
  if (compression == "zstd") o.compress = zstd;
  const std::string path = dir.file("f_" + compression + ".mcap");
  Writer w(path, o);
  const uint16_t s = w.addSchema("test_msgs/msg/Blob", "ros2msg", "uint8[] data");
  const uint16_t a = w.addChannel(s, "/a", "cdr");
  const uint16_t b = w.addChannel(s, "/b", "cdr");
  for (int i = 0; i < 80; ++i) {
    const std::string data(100, static_cast<char>('A' + i % 26));
    w.write(i < 40 ? a : b, 1000 + static_cast<uint64_t>(i), 1000 + static_cast<uint64_t>(i),
            data.data(), data.size());
  }
  w.close();
  return path;
}

struct Read {
  std::vector<std::pair<std::string, uint64_t>> messages;  // topic, log time
  ReaderStats stats;
};

Read readAll(Reader& r) {
  Read out;
  ReadMessage m;
  while (r.next(m)) {
    EXPECT_EQ(m.data.size(), 100u);
    out.messages.emplace_back(m.channel->topic, m.header.log_time);
  }
  out.stats = r.stats();
  return out;
}

// Reads to the end, whatever comes out (damaged files).
size_t drain(Reader& r) {
  size_t n = 0;
  ReadMessage m;
  while (r.next(m)) ++n;
  return n;
}

// The records' CRC-32 (slicing-by-8) is the IEEE one byte by byte: the standard check value, and
// every length and split of a buffer, continued across calls as the reader and writer do.
TEST(McapCrc32, IsTheIeeeCrcOverAnyLengthAndSplit) {
  EXPECT_EQ(mcap::crc32("123456789", 9), 0xCBF43926u);
  EXPECT_EQ(mcap::crc32("", 0), 0u);
  std::string data(1000, '\0');
  uint32_t x = 12345;
  for (char& c : data) c = static_cast<char>((x = x * 1103515245u + 12345u) >> 24);
  const auto bytewise = [](const std::string& d, size_t n) {
    uint32_t crc = ~0u;
    for (size_t i = 0; i < n; ++i) {
      crc ^= static_cast<uint8_t>(d[i]);
      for (int k = 0; k < 8; ++k) crc = (crc & 1) ? 0xEDB88320u ^ (crc >> 1) : crc >> 1;
    }
    return ~crc;
  };
  for (size_t n : {1u, 7u, 8u, 9u, 15u, 16u, 17u, 63u, 64u, 999u, 1000u}) {
    const uint32_t want = bytewise(data, n);
    EXPECT_EQ(mcap::crc32(data.data(), n), want) << n << " bytes";
    for (size_t split : {size_t{0}, size_t{1}, size_t{3}, n / 2, n - 1}) {
      if (split > n) continue;
      EXPECT_EQ(mcap::crc32(data.data() + split, n - split, mcap::crc32(data.data(), split)), want)
          << n << " bytes split at " << split;
    }
  }
}

TEST(McapReader, IndexedAndScannedReadsAgreeForEveryCompression) {
  plugslam::testing::TempDir dir;
  for (const std::string c : {"", "lz4", "zstd"}) {
    SCOPED_TRACE("compression '" + c + "'");
    const std::string path = makeFile(dir, c);
    Reader indexed(path);
    EXPECT_EQ(indexed.header().profile, "ros2");
    ASSERT_TRUE(indexed.statistics().has_value());
    EXPECT_EQ(indexed.statistics()->message_count, 80u);
    EXPECT_EQ(indexed.channels().size(), 2u);  // known before any message: from the summary
    const Read a = readAll(indexed);
    ReaderOptions scan;
    scan.use_summary = false;
    Reader scanned(path, scan);
    const Read b = readAll(scanned);
    EXPECT_TRUE(a.stats.indexed);
    EXPECT_FALSE(b.stats.indexed);
    ASSERT_EQ(a.messages.size(), 80u);
    EXPECT_EQ(a.messages, b.messages);
    for (size_t i = 0; i < a.messages.size(); ++i) EXPECT_EQ(a.messages[i].second, 1000 + i);
    EXPECT_GT(a.stats.chunks, 3u);  // the chunk size makes several
    EXPECT_EQ(a.stats.compression.count(c), 1u);
  }
}

TEST(McapReader, TopicFilterSkipsChunksOfOtherTopics) {
  plugslam::testing::TempDir dir;
  const std::string path = makeFile(dir, "zstd");
  ReaderOptions o;
  o.topics = {"/b"};
  Reader r(path, o);
  const Read got = readAll(r);
  ASSERT_EQ(got.messages.size(), 40u);
  for (const auto& [topic, t] : got.messages) EXPECT_EQ(topic, "/b");
  // /a fills the first chunks alone: the index shows they hold nothing wanted.
  EXPECT_GT(got.stats.chunks_skipped, 0u);
}

TEST(McapReader, NotMcapIsAParseErrorAtOffsetZero) {
  try {
    Reader::fromBytes("x.mcap", "#ROSBAG V2.0\nnot mcap at all");
    FAIL() << "no error";
  } catch (const ParseError& e) {
    EXPECT_EQ(e.file(), "x.mcap");
    EXPECT_NE(std::string(e.what()).find("byte offset 0"), std::string::npos) << e.what();
  }
}

TEST(McapReader, ACutFileKeepsTheMessagesBeforeTheCut) {
  plugslam::testing::TempDir dir;
  const std::string bytes = slurp(makeFile(dir, "lz4"));
  // Cut in the middle of the data section: no footer, so it is scanned up to the cut.
  auto r = Reader::fromBytes("cut.mcap", bytes.substr(0, bytes.size() / 2));
  const Read got = readAll(*r);
  EXPECT_FALSE(got.stats.indexed);
  EXPECT_GT(got.stats.truncated_at, 0u);
  EXPECT_LT(got.stats.truncated_at, bytes.size() / 2);
  EXPECT_GT(got.messages.size(), 10u);
  EXPECT_LT(got.messages.size(), 80u);
}

TEST(McapReader, EveryCutAndEveryFlippedByteIsAnErrorOrAWarningNeverACrash) {
  plugslam::testing::TempDir dir;
  for (const std::string c : {"", "lz4", "zstd"}) {
    const std::string bytes = slurp(makeFile(dir, c));
    size_t errors = 0;
    for (size_t n = 0; n < bytes.size(); n += 97) {  // steps prime to the record sizes
      try {
        auto r = Reader::fromBytes("cut.mcap", bytes.substr(0, n));
        EXPECT_LE(drain(*r), 80u);
      } catch (const InputError&) {
        ++errors;
      }
    }
    EXPECT_GT(errors, 0u);  // a cut inside the magic or the header record
    for (size_t at = 0; at < bytes.size(); at += 131) {
      std::string flipped = bytes;
      flipped[at] = static_cast<char>(flipped[at] ^ 0x5A);
      for (const bool summary : {true, false}) {
        ReaderOptions o;
        o.use_summary = summary;
        try {
          auto r = Reader::fromBytes("flipped.mcap", flipped, o);
          drain(*r);
        } catch (const InputError&) {
          ++errors;
        }
      }
    }
    EXPECT_GT(errors, 10u) << "compression '" << c << "'";
  }
}

// Offset of the first chunk's records in a file of makeFile (magic, header record, chunk).
size_t firstChunkRecords(const std::string& bytes, size_t compression_name) {
  size_t at = 8;
  uint64_t len = 0;
  for (int k = 0; k < 8; ++k) len |= uint64_t{static_cast<uint8_t>(bytes[at + 1 + k])} << (8 * k);
  at += 9 + len;  // the chunk record
  EXPECT_EQ(bytes[at], static_cast<char>(Op::kChunk));
  return at + 9 + 8 + 8 + 8 + 4 + 4 + compression_name + 8;
}

TEST(McapReader, ABadChunkCrcNamesTheFileAndTheChunkOffset) {
  plugslam::testing::TempDir dir;
  std::string bytes = slurp(makeFile(dir, ""));
  bytes[firstChunkRecords(bytes, 0) + 60] ^= 0x01;  // inside the first chunk's records
  for (const bool summary : {true, false}) {
    ReaderOptions o;
    o.use_summary = summary;
    try {
      auto r = Reader::fromBytes("crc.mcap", bytes, o);
      readAll(*r);
      FAIL() << "no error";
    } catch (const ParseError& e) {
      EXPECT_EQ(e.file(), "crc.mcap");
      EXPECT_NE(std::string(e.what()).find("CRC mismatch"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("byte offset "), std::string::npos) << e.what();
    }
  }
}

TEST(McapReader, AChunkThatDoesNotDecompressIsAnError) {
  plugslam::testing::TempDir dir;
  for (const std::string c : {"lz4", "zstd"}) {
    std::string bytes = slurp(makeFile(dir, c));
    const size_t records = firstChunkRecords(bytes, c.size());
    for (size_t k = 0; k < 8; ++k) bytes[records + k] = '\xFF';  // the frame's magic and header
    try {
      auto r = Reader::fromBytes("bad.mcap", bytes);
      readAll(*r);
      FAIL() << "no error for " << c;
    } catch (const ParseError& e) {
      EXPECT_NE(std::string(e.what()).find("does not decompress"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(c), std::string::npos) << e.what();
    }
  }
}

TEST(McapReader, ABadSummaryCrcIsAnError) {
  plugslam::testing::TempDir dir;
  std::string bytes = slurp(makeFile(dir, ""));
  // The footer's summary_start (8 bytes after its prefix), then flip a byte of the summary.
  const size_t footer = bytes.size() - 8 - 29;
  uint64_t start = 0;
  for (int k = 0; k < 8; ++k) start |= uint64_t{static_cast<uint8_t>(bytes[footer + 9 + k])} << (8 * k);
  ASSERT_GT(start, 0u);
  bytes[start + 12] ^= 0x01;
  EXPECT_THROW(Reader::fromBytes("summary.mcap", bytes), ParseError);
}

uint64_t le64At(const std::string& bytes, size_t at) {
  uint64_t v = 0;
  for (int k = 0; k < 8; ++k) v |= uint64_t{static_cast<uint8_t>(bytes[at + k])} << (8 * k);
  return v;
}

// Data End's data_section_crc covers the bytes no other CRC does: those between the chunks (the
// message indexes), which a scan does not use but which say the file was damaged.
TEST(McapReader, ADamagedDataSectionIsAnErrorWhenScannedUnlessItsCrcIsUnset) {
  plugslam::testing::TempDir dir;
  std::string bytes = slurp(makeFile(dir, ""));
  const size_t chunk = 8 + 9 + le64At(bytes, 8 + 1);
  const size_t index = chunk + 9 + le64At(bytes, chunk + 1);  // the first chunk's message index
  ASSERT_EQ(bytes[index], static_cast<char>(Op::kMessageIndex));
  bytes[index + 9 + 2 + 4 + 3] ^= 0x01;  // its first entry's log time
  ReaderOptions scan;
  scan.use_summary = false;
  try {
    auto r = Reader::fromBytes("data.mcap", bytes, scan);
    readAll(*r);
    FAIL() << "no error";
  } catch (const ParseError& e) {
    EXPECT_EQ(e.file(), "data.mcap");
    EXPECT_NE(std::string(e.what()).find("data section CRC mismatch"), std::string::npos)
        << e.what();
  }
  // The indexed read uses chunks whose own CRCs hold: it reads them all.
  auto indexed = Reader::fromBytes("data.mcap", bytes);
  EXPECT_EQ(drain(*indexed), 80u);
  // Data End sits right before the summary; a CRC of 0 means the writer computed none.
  const size_t footer = bytes.size() - 8 - 29;
  const uint64_t summary = le64At(bytes, footer + 9);
  ASSERT_EQ(bytes[summary - 13], static_cast<char>(Op::kDataEnd));
  for (size_t k = 0; k < 4; ++k) bytes[summary - 4 + k] = 0;
  auto unset = Reader::fromBytes("data.mcap", bytes, scan);
  EXPECT_EQ(drain(*unset), 80u);
}

}  // namespace
}  // namespace plugslam::mcap
