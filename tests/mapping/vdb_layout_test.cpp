// The map.vdb head check against OpenVDB's own writer: what pensight writes passes, zip or blosc,
// other grids and every truncation are refused with an Error.
#include "mapping/vdb_layout.h"

#include <gtest/gtest.h>
#include <openvdb/io/Stream.h>
#include <openvdb/openvdb.h>

#include <random>
#include <sstream>
#include <string>

#include "core/error.h"
#include "tests/support/vulkan_fixture.h"

namespace pensight::mapping {
namespace {

openvdb::GridPtrVec random_float_grid(uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_int_distribution<int> coord(-40, 40);
  auto grid = openvdb::FloatGrid::create(0.0f);
  grid->setName("occupancy");
  auto acc = grid->getAccessor();
  for (int i = 0; i < 300; ++i) acc.setValue({coord(rng), coord(rng), coord(rng)}, 0.5f);
  return {grid};
}

std::string written(const openvdb::GridPtrVec& grids, uint32_t compression) {
  std::ostringstream out(std::ios::binary);
  openvdb::io::Stream stream(out);
  stream.setCompression(compression);
  stream.write(grids);
  return out.str();
}

TEST(VdbLayout, MaskCompressionPassesZipAndBloscAreRefused) {
  openvdb::initialize();
  const auto grids = random_float_grid(testing::fresh_seed());
  EXPECT_NO_THROW(check_vdb_layout(written(grids, openvdb::io::COMPRESS_ACTIVE_MASK)));
  EXPECT_NO_THROW(check_vdb_layout(written(grids, openvdb::io::COMPRESS_NONE)));
  for (uint32_t c : {openvdb::io::COMPRESS_ZIP | openvdb::io::COMPRESS_ACTIVE_MASK,
                     openvdb::io::COMPRESS_BLOSC | openvdb::io::COMPRESS_ACTIVE_MASK}) {
    try {
      check_vdb_layout(written(grids, c));
      ADD_FAILURE() << "compression " << c << " passed";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("zip or blosc"), std::string::npos) << e.what();
    }
  }
}

TEST(VdbLayout, OtherGridsAndEveryTruncationAreErrors) {
  openvdb::initialize();
  auto grids = random_float_grid(testing::fresh_seed());
  const std::string good = written(grids, openvdb::io::COMPRESS_ACTIVE_MASK);
  grids.push_back(openvdb::FloatGrid::create());
  EXPECT_THROW(check_vdb_layout(written(grids, openvdb::io::COMPRESS_ACTIVE_MASK)), Error);
  EXPECT_THROW(
      check_vdb_layout(written({openvdb::Vec3SGrid::create()}, openvdb::io::COMPRESS_ACTIVE_MASK)),
      Error);
  // Every cut before the first grid's flags is an Error; the check reads no further (the head
  // of this file is about 300 bytes of its several kB).
  size_t head = 0;
  while (head < good.size()) {
    try {
      check_vdb_layout(std::string_view(good).substr(0, head));
      break;
    } catch (const Error&) {
      ++head;
    }
  }
  EXPECT_LT(head, 400u);
  EXPECT_GT(good.size(), 2 * head);
}

}  // namespace
}  // namespace pensight::mapping
