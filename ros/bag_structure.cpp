#include "ros/bag_structure.h"

#include <bzlib.h>
#include <roslz4/lz4s.h>

#include <algorithm>
#include <fstream>
#include <iterator>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "core/error.h"

namespace pensight {
namespace fs = std::filesystem;
namespace {

constexpr char kMagic[] = "#ROSBAG V2.0\n";
constexpr uint64_t kMagicBytes = sizeof kMagic - 1;
// Record ops (the `op` header field).
constexpr uint8_t kMessageData = 0x02, kBagHeader = 0x03, kIndexData = 0x04, kChunk = 0x05,
                  kChunkInfo = 0x06, kConnection = 0x07;

uint64_t little_endian(const std::string& bytes) {
  uint64_t v = 0;
  for (size_t i = bytes.size(); i-- > 0;) v = (v << 8) | static_cast<uint8_t>(bytes[i]);
  return v;
}

// A byte range of the file (or of an uncompressed chunk read into memory) and its records.
class Records {
 public:
  Records(const fs::path& file, std::istream& in, uint64_t begin, uint64_t end, std::string where)
      : file_(file), in_(in), pos_(begin), end_(end), where_(std::move(where)) {}

  bool done() const { return pos_ >= end_; }

  struct Record {
    uint64_t offset = 0;  // of its header length
    std::map<std::string, std::string> fields;
    uint64_t data_offset = 0, data_bytes = 0;
  };

  Record next() {
    Record r;
    r.offset = pos_;
    const uint64_t header_bytes = length("record header length");
    const std::string header = read(header_bytes);
    r.fields = fields(header, pos_ - header_bytes);
    r.data_bytes = length("record data length");
    r.data_offset = pos_;
    if (r.data_bytes > end_ - pos_) fail(r.data_offset, "record data runs past the end");
    pos_ += r.data_bytes;
    return r;
  }

  std::string read_data(const Record& r) {
    const uint64_t keep = pos_;
    pos_ = r.data_offset;
    std::string data = read(r.data_bytes);
    pos_ = keep;
    return data;
  }

  // The fields of a header (name=value, each behind its 4-byte length).
  std::map<std::string, std::string> fields(const std::string& header, uint64_t offset) const {
    std::map<std::string, std::string> out;
    size_t i = 0;
    while (i < header.size()) {
      if (header.size() - i < 4) fail(offset + i, "a header field length is cut short");
      const uint64_t n = little_endian(header.substr(i, 4));
      i += 4;
      if (n > header.size() - i) fail(offset + i, "a header field runs past its header");
      const std::string field = header.substr(i, n);
      const size_t eq = field.find('=');
      if (eq == std::string::npos) fail(offset + i, "a header field has no '='");
      out[field.substr(0, eq)] = field.substr(eq + 1);
      i += n;
    }
    return out;
  }

  [[noreturn]] void fail(uint64_t offset, const std::string& what) const {
    throw Error("'" + file_.string() + "' is not a readable ROS 1 bag: damaged at byte " +
                std::to_string(offset) + where_ + ": " + what +
                " (cut short or corrupted; `rosbag reindex` repairs an interrupted recording, "
                "`rosbag check` names a bag's problems)");
  }

 private:
  uint64_t length(const char* what) {
    if (end_ - pos_ < 4) fail(pos_, std::string(what) + " is cut short");
    const uint64_t n = little_endian(read(4));
    if (n > end_ - pos_)
      fail(pos_ - 4, std::string(what) + " " + std::to_string(n) + " runs past the end");
    return n;
  }

  std::string read(uint64_t bytes) {
    std::string out(bytes, '\0');
    in_.seekg(static_cast<std::streamoff>(pos_));
    in_.read(out.data(), static_cast<std::streamsize>(bytes));
    if (!in_) fail(pos_, "cannot read " + std::to_string(bytes) + " bytes");
    pos_ += bytes;
    return out;
  }

  const fs::path& file_;
  std::istream& in_;
  uint64_t pos_, end_;
  std::string where_;
};

const std::string& field(const Records& records, const Records::Record& r, const char* name,
                         size_t bytes) {
  const auto it = r.fields.find(name);
  if (it == r.fields.end() || (bytes > 0 && it->second.size() != bytes)) {
    records.fail(r.offset, std::string("a record without a ") + std::to_string(bytes) + "-byte '" +
                               name + "' field");
  }
  return it->second;
}

uint8_t op_of(const Records& records, const Records::Record& r) {
  return static_cast<uint8_t>(field(records, r, "op", 1)[0]);
}

// The records of a chunk (uncompressed): message data and connections. Returns the offsets of
// its message data records, where the index records that follow the chunk must point.
std::set<uint64_t> chunk_records(const fs::path& file, const std::string& chunk,
                                 uint64_t chunk_offset) {
  std::istringstream in(chunk);
  Records records(file, in, 0, chunk.size(),
                  " (offset in the chunk at byte " + std::to_string(chunk_offset) + ")");
  std::set<uint64_t> messages;
  while (!records.done()) {
    const Records::Record r = records.next();
    const uint8_t op = op_of(records, r);
    if (op == kMessageData) {
      messages.insert(r.offset);
    } else if (op == kConnection) {
      records.fields(records.read_data(r), r.data_offset);
    } else {
      records.fail(r.offset, "a chunk holds a record of op " + std::to_string(op));
    }
  }
  return messages;
}

// A chunk's records as rosbag will see them: unpacked as its compression says.
std::string unpacked_chunk(const Records& records, const Records::Record& r, std::string data) {
  const std::string& compression = field(records, r, "compression", 0);
  const uint64_t bytes = little_endian(field(records, r, "size", 4));
  if (compression == "none") {
    if (bytes != data.size()) {
      records.fail(r.offset, "an uncompressed chunk of " + std::to_string(data.size()) +
                                 " bytes says it has " + std::to_string(bytes));
    }
    return data;
  }
  if (compression != "bz2" && compression != "lz4") {
    records.fail(r.offset,
                 "chunk compression '" + compression + "' (rosbag writes none, bz2 or lz4)");
  }
  if (bytes > kMaxBagChunkBytes) {
    records.fail(r.offset, "a chunk says it unpacks to " + std::to_string(bytes) +
                               " bytes (at most " + std::to_string(kMaxBagChunkBytes) +
                               " are read)");
  }
  std::string out(bytes, '\0');
  auto out_bytes = static_cast<unsigned int>(bytes);
  const auto in_bytes = static_cast<unsigned int>(data.size());
  const bool ok =
      compression == "bz2"
          ? BZ2_bzBuffToBuffDecompress(out.data(), &out_bytes, data.data(), in_bytes, 0, 0) == BZ_OK
          : roslz4_buffToBuffDecompress(data.data(), in_bytes, out.data(), &out_bytes) == ROSLZ4_OK;
  if (!ok || out_bytes != bytes) {
    records.fail(r.data_offset, "a " + compression + " chunk does not unpack to the " +
                                    std::to_string(bytes) + " bytes it says");
  }
  return out;
}

}  // namespace

void check_bag_structure(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw Error("cannot open bag '" + file.string() + "'");
  const uint64_t size = fs::file_size(file);
  std::string magic(kMagicBytes, '\0');
  in.read(magic.data(), static_cast<std::streamsize>(kMagicBytes));
  if (!in || magic != kMagic) {
    throw Error("'" + file.string() +
                "' is not a ROS 1 bag (no '#ROSBAG V2.0' line at its "
                "start): pensight reads ROS 1 .bag files (format 2.0), not ROS 2 bags");
  }
  Records records(file, in, kMagicBytes, size, "");
  std::set<uint64_t> messages_in_chunk;
  struct ChunkInfo {
    uint64_t offset, chunk, connections;
  };
  std::vector<ChunkInfo> chunk_infos;
  std::vector<std::pair<uint64_t, uint8_t>> walked;  // every record's offset and op, in order
  uint64_t header_offset = 0, index = 0, connections = 0, chunk_count = 0;
  while (!records.done()) {
    const Records::Record r = records.next();
    walked.emplace_back(r.offset, op_of(records, r));
    switch (walked.back().second) {
      case kBagHeader: {
        header_offset = r.offset;
        index = little_endian(field(records, r, "index_pos", 8));
        connections = little_endian(field(records, r, "conn_count", 4));
        chunk_count = little_endian(field(records, r, "chunk_count", 4));
        if (index < kMagicBytes || index > size) {
          records.fail(r.offset,
                       "the index position " + std::to_string(index) + " lies outside the file");
        }
        break;
      }
      case kChunk:
        messages_in_chunk =
            chunk_records(file, unpacked_chunk(records, r, records.read_data(r)), r.data_offset);
        break;
      case kIndexData: {
        const uint64_t count = little_endian(field(records, r, "count", 4));
        if (little_endian(field(records, r, "ver", 4)) != 1 || r.data_bytes != 12 * count) {
          records.fail(r.offset, "an index record of " + std::to_string(r.data_bytes) +
                                     " bytes for " + std::to_string(count) + " entries");
        }
        // Entries of (time, offset in the chunk before it): rosbag reads a message there.
        const std::string entries = records.read_data(r);
        for (uint64_t i = 0; i < count; ++i) {
          const uint64_t at = little_endian(entries.substr(12 * i + 8, 4));
          if (!messages_in_chunk.contains(at)) {
            records.fail(r.data_offset + 12 * i, "an index entry points at byte " +
                                                     std::to_string(at) +
                                                     " of its chunk, where no message starts");
          }
        }
        break;
      }
      case kChunkInfo: {
        const uint64_t count = little_endian(field(records, r, "count", 4));
        const uint64_t chunk = little_endian(field(records, r, "chunk_pos", 8));
        chunk_infos.push_back({r.offset, chunk, count});
        if (little_endian(field(records, r, "ver", 4)) != 1 || r.data_bytes != 8 * count) {
          records.fail(r.offset, "a chunk-info record of " + std::to_string(r.data_bytes) +
                                     " bytes for " + std::to_string(count) + " connections");
        }
        break;
      }
      case kConnection:
        records.fields(records.read_data(r), r.data_offset);
        break;
      default:
        break;  // rosbag names records it does not know
    }
  }
  // rosbag reads conn_count connection records and then chunk_count chunk-info records from the
  // index position on, and after each chunk as many index records as its chunk-info counts: a
  // position or count off the records makes it take other bytes for a record's lengths.
  // `walked` is in file order, so sorted by offset: a binary search per lookup (a long bag has
  // tens of thousands of chunks and records).
  const auto record_at = [&](uint64_t offset) {
    const auto at = std::lower_bound(walked.begin(), walked.end(), offset,
                                     [](const auto& w, uint64_t o) { return w.first < o; });
    return at != walked.end() && at->first == offset ? at : walked.end();
  };
  const auto expect_records = [&](auto from, uint64_t count, uint8_t op, uint64_t named_at,
                                  const std::string& what) {
    for (uint64_t i = 0; i < count; ++i, ++from) {
      if (from == walked.end() || from->second != op) {
        records.fail(named_at, what + ": record " + std::to_string(i + 1) + " of " +
                                   std::to_string(count) + " is not there");
      }
    }
    return from;
  };
  if (index != 0 && connections + chunk_count > 0) {  // 0: unindexed, rosbag's own error
    const auto at = record_at(index);
    if (at == walked.end()) {
      records.fail(header_offset,
                   "the index position " + std::to_string(index) + " is not the start of a record");
    }
    const std::string where = "the index at byte " + std::to_string(index);
    expect_records(
        expect_records(at, connections, kConnection, index,
                       where + " lacks the bag header's " + std::to_string(connections) +
                           " connection records"),
        chunk_count, kChunkInfo, index,
        where + " lacks the bag header's " + std::to_string(chunk_count) + " chunk-info records");
  }
  for (const ChunkInfo& c : chunk_infos) {
    const auto chunk = record_at(c.chunk);
    if (chunk == walked.end() || chunk->second != kChunk) {
      records.fail(c.offset, "a chunk-info record points at byte " + std::to_string(c.chunk) +
                                 ", where no chunk starts");
    }
    expect_records(std::next(chunk), c.connections, kIndexData, c.chunk,
                   "the chunk at byte " + std::to_string(c.chunk) + " lacks the " +
                       std::to_string(c.connections) + " index records its chunk-info counts");
  }
}

}  // namespace pensight
