#include "mapping/vdb_layout.h"

#include <openvdb/openvdb.h>

#include <cstdint>
#include <cstring>
#include <string>

#include "core/error.h"

namespace pensight::mapping {
namespace {

// A read position in the file's bytes; every read is checked against their end.
class Cursor {
 public:
  explicit Cursor(std::string_view bytes) : bytes_(bytes) {}
  template <class T>
  T read() {
    T value;
    std::memcpy(&value, take(sizeof(T)).data(), sizeof(T));
    return value;
  }
  std::string_view take(size_t n) {
    if (n > bytes_.size() - at_) throw Error("truncated (the file ends inside its header)");
    const std::string_view out = bytes_.substr(at_, n);
    at_ += n;
    return out;
  }
  std::string_view string() { return take(read<uint32_t>()); }  // OpenVDB's readString

 private:
  std::string_view bytes_;
  size_t at_ = 0;
};

}  // namespace

void check_vdb_layout(std::string_view bytes) {
  Cursor in(bytes);
  if (bytes.size() < 8 || in.read<int64_t>() != openvdb::OPENVDB_MAGIC) {
    throw Error("not an OpenVDB file (no VDB magic number)");
  }
  const auto version = in.read<uint32_t>();
  if (version < openvdb::OPENVDB_FILE_VERSION_NODE_MASK_COMPRESSION ||
      version > openvdb::OPENVDB_FILE_VERSION) {
    throw Error("OpenVDB file version " + std::to_string(version) + " (pensight reads " +
                std::to_string(openvdb::OPENVDB_FILE_VERSION_NODE_MASK_COMPRESSION) + "-" +
                std::to_string(openvdb::OPENVDB_FILE_VERSION) + "; re-run pensight map)");
  }
  in.take(4 + 4 + 1 + 36);  // library major, minor; has-grid-offsets flag; UUID as text
  const auto meta_count = in.read<uint32_t>();
  for (uint32_t i = 0; i < meta_count; ++i) {
    in.string();  // name
    in.string();  // type name
    in.string();  // value: its byte count, then the bytes
  }
  if (const auto grids = in.read<int32_t>(); grids != 1) {
    throw Error("holds " + std::to_string(grids) + " grids (a pensight map holds one)");
  }
  in.string();  // unique name
  if (const std::string_view type = in.string(); type != openvdb::FloatGrid::gridType()) {
    throw Error("grid of type '" + std::string(type) + "' (a pensight map is a " +
                openvdb::FloatGrid::gridType() + ")");
  }
  if (!in.string().empty()) throw Error("its grid is an instance of another grid");
  in.take(3 * sizeof(int64_t));  // grid, block and end positions
  const auto compression = in.read<uint32_t>();
  if (compression & (openvdb::io::COMPRESS_ZIP | openvdb::io::COMPRESS_BLOSC)) {
    throw Error(
        "grid stored with zip or blosc compression, which OpenVDB 10 cannot read safely "
        "(pensight map writes without; re-run it)");
  }
}

}  // namespace pensight::mapping
