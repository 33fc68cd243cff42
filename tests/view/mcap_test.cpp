// The MCAP record layer and writer, checked byte by byte against the spec (mcap.dev/spec): the
// magic, the records' framing, chunk CRCs, message indexes pointing at their messages, the data
// section CRC, the summary offsets and the summary CRC. (@mcap/core's readers check the same
// files in tests/node/mcap_test.js.)
#include <gtest/gtest.h>

#include <boost/filesystem.hpp>
#include <fstream>
#include <iterator>
#include <map>

#include "plugslam/errors.h"
#include "plugslam/mcap/writer.h"
#include "temp_dir.h"

namespace plugslam::mcap {
namespace {

namespace fs = boost::filesystem;

uint64_t le(const std::string& b, size_t at, int bytes) {
  uint64_t v = 0;
  for (int i = 0; i < bytes; ++i) v |= static_cast<uint64_t>(static_cast<uint8_t>(b.at(at + i))) << (8 * i);
  return v;
}

struct Record {
  uint8_t op;
  size_t start;    // offset of the opcode
  size_t content;  // offset of the content
  uint64_t length;
};

// Splits [from, to) of `b` into records, checking each fits.
std::vector<Record> records(const std::string& b, size_t from, size_t to) {
  std::vector<Record> out;
  for (size_t at = from; at < to;) {
    EXPECT_LE(at + 9, to);
    const uint64_t n = le(b, at + 1, 8);
    EXPECT_LE(at + 9 + n, to);
    out.push_back(Record{static_cast<uint8_t>(b[at]), at, at + 9, n});
    at += 9 + n;
  }
  return out;
}

class McapWriterTest : public ::testing::Test {
 protected:
  void SetUp() override { dir_ = tmp_.path().string(); }
  std::string read(const fs::path& p) {
    std::ifstream in(p.string(), std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
  }
  plugslam::testing::TempDir tmp_{"plugslam_mcap"};  // fresh, of this test's own, removed after
  fs::path dir_;
};

TEST(McapCrc, MatchesTheCheckValue) {
  EXPECT_EQ(crc32("123456789", 9), 0xCBF43926u);  // the CRC-32/ISO-HDLC check value
  EXPECT_EQ(crc32("56789", 5, crc32("1234", 4)), 0xCBF43926u);  // continued
  EXPECT_EQ(crc32("", 0), 0u);
}

TEST_F(McapWriterTest, WritesAnIndexedFileTheSpecDescribes) {
  const fs::path path = dir_ / "t.mcap";
  std::map<uint64_t, std::string> sent;  // log time -> data
  {
    WriterOptions o;
    o.chunk_size = 200;  // several chunks
    Writer w(path.string(), o);
    const uint16_t schema = w.addSchema("foxglove.Log", "jsonschema", "{}");
    const uint16_t a = w.addChannel(schema, "/a", "json");
    const uint16_t b = w.addChannel(schema, "/b", "json", {{"k", "v"}});
    for (uint64_t t = 1; t <= 40; ++t) {
      const std::string data = "{\"n\":" + std::to_string(t) + "}";
      w.write(t % 3 ? a : b, t * 1000, t * 1000, data.data(), data.size());
      sent[t * 1000] = data;
    }
    w.close();
    EXPECT_EQ(w.messages(), 40u);
  }
  const std::string f = read(path);
  ASSERT_GT(f.size(), 16u);
  EXPECT_EQ(f.substr(0, 8), std::string(kMagic, 8));
  EXPECT_EQ(f.substr(f.size() - 8), std::string(kMagic, 8));

  // Footer: the last record before the magic.
  const size_t footer_at = f.size() - 8 - 29;
  ASSERT_EQ(static_cast<uint8_t>(f[footer_at]), static_cast<uint8_t>(Op::kFooter));
  const uint64_t summary_start = le(f, footer_at + 9, 8);
  const uint64_t summary_offset_start = le(f, footer_at + 17, 8);
  const uint32_t summary_crc = static_cast<uint32_t>(le(f, footer_at + 25, 4));
  EXPECT_EQ(summary_crc, crc32(f.data() + summary_start, footer_at + 25 - summary_start));

  // The data section: header, chunks each followed by its message indexes, then Data End.
  auto data = records(f, 8, summary_start);
  ASSERT_GE(data.size(), 3u);
  EXPECT_EQ(data.front().op, static_cast<uint8_t>(Op::kHeader));
  const Record& end = data.back();
  ASSERT_EQ(end.op, static_cast<uint8_t>(Op::kDataEnd));
  EXPECT_EQ(le(f, end.content, 4), crc32(f.data(), end.start));
  size_t chunks = 0, messages = 0;
  std::map<uint64_t, size_t> chunk_at;  // chunk offset -> index in `data`
  for (size_t i = 0; i < data.size(); ++i) {
    const Record& r = data[i];
    if (r.op != static_cast<uint8_t>(Op::kChunk)) continue;
    ++chunks;
    chunk_at[r.start] = i;
    const uint64_t size = le(f, r.content + 16, 8);
    const uint32_t crc = static_cast<uint32_t>(le(f, r.content + 24, 4));
    const uint64_t clen = le(f, r.content + 28, 4);
    EXPECT_EQ(clen, 0u);  // uncompressed
    const size_t records_at = r.content + 32 + clen + 8;
    ASSERT_EQ(le(f, r.content + 32 + clen, 8), size);
    EXPECT_EQ(crc, crc32(f.data() + records_at, size));
    // Inside: schema, channel and message records; each message index entry points at one.
    std::map<size_t, uint64_t> in_chunk;  // offset -> log time of its Message records
    for (const Record& inner : records(f, records_at, records_at + size))
      if (inner.op == static_cast<uint8_t>(Op::kMessage)) {
        const uint64_t t = le(f, inner.content + 6, 8);
        const std::string payload = f.substr(inner.content + 22, inner.length - 22);
        EXPECT_EQ(payload, sent.at(t));
        in_chunk[inner.start - records_at] = t;
        ++messages;
      }
    size_t indexed = 0;
    for (size_t j = i + 1; j < data.size() && data[j].op == static_cast<uint8_t>(Op::kMessageIndex); ++j) {
      const Record& mi = data[j];
      const uint64_t bytes = le(f, mi.content + 2, 4);
      for (uint64_t e = 0; e < bytes; e += 16) {
        const uint64_t t = le(f, mi.content + 6 + e, 8), off = le(f, mi.content + 14 + e, 8);
        ASSERT_TRUE(in_chunk.count(off)) << "index entry points at no message";
        EXPECT_EQ(in_chunk[off], t);
        ++indexed;
      }
    }
    EXPECT_EQ(indexed, in_chunk.size());
  }
  EXPECT_GT(chunks, 3u);
  EXPECT_EQ(messages, 40u);

  // The summary: groups located by Summary Offset records; chunk indexes point at chunks.
  auto summary = records(f, summary_start, summary_offset_start);
  auto offsets = records(f, summary_offset_start, footer_at);
  std::map<uint8_t, size_t> count;
  for (const Record& r : summary) ++count[r.op];
  EXPECT_EQ(count[static_cast<uint8_t>(Op::kSchema)], 1u);
  EXPECT_EQ(count[static_cast<uint8_t>(Op::kChannel)], 2u);
  EXPECT_EQ(count[static_cast<uint8_t>(Op::kChunkIndex)], chunks);
  EXPECT_EQ(count[static_cast<uint8_t>(Op::kStatistics)], 1u);
  EXPECT_EQ(offsets.size(), 4u);
  for (const Record& o : offsets) {
    const uint8_t op = static_cast<uint8_t>(f[o.content]);
    const uint64_t start = le(f, o.content + 1, 8), length = le(f, o.content + 9, 8);
    uint64_t total = 0;
    for (const Record& r : summary)
      if (r.op == op) {
        EXPECT_GE(r.start, start);
        total += 9 + r.length;
      }
    EXPECT_EQ(length, total);
    EXPECT_EQ(static_cast<uint8_t>(f[start]), op);
  }
  for (const Record& r : summary) {
    if (r.op == static_cast<uint8_t>(Op::kStatistics)) {
      EXPECT_EQ(le(f, r.content, 8), 40u);
    }
    if (r.op != static_cast<uint8_t>(Op::kChunkIndex)) continue;
    const uint64_t at = le(f, r.content + 16, 8), length = le(f, r.content + 24, 8);
    ASSERT_TRUE(chunk_at.count(at));
    EXPECT_EQ(length, 9 + data[chunk_at[at]].length);
  }
}

TEST_F(McapWriterTest, AnEmptyRecordingIsValid) {
  const fs::path path = dir_ / "empty.mcap";
  Writer(path.string()).close();
  const std::string f = read(path);
  EXPECT_EQ(f.substr(0, 8), std::string(kMagic, 8));
  EXPECT_EQ(f.substr(f.size() - 8), std::string(kMagic, 8));
  const size_t footer_at = f.size() - 8 - 29;
  EXPECT_EQ(static_cast<uint8_t>(f[footer_at]), static_cast<uint8_t>(Op::kFooter));
}

TEST_F(McapWriterTest, AnUnwritableFileIsAnInputError) {
  EXPECT_THROW(Writer((dir_ / "no" / "such" / "dir" / "x.mcap").string()), InputError);
}

}  // namespace
}  // namespace plugslam::mcap
