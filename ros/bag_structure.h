#pragma once
// The record structure of a ROS 1 bag (format 2.0, wiki.ros.org/Bags/Format/2.0), checked before
// rosbag reads the file. rosbag trusts the lengths and offsets it reads: a damaged bag makes it
// allocate what a length field says (gigabytes) or read a message at an offset past its chunk.
// Checked here: the magic line; every record's header and data fit in the file (or its chunk),
// every header field in its header; the bag header's index position is the start of as many
// connection records and then chunk-info records as it counts; a chunk is none, bz2 or lz4,
// claims at most kMaxBagChunkBytes and unpacks to exactly its size, holds only message data and
// connection records, and is followed by as many index records as its chunk-info counts; every
// index entry points at a message record of the chunk before it, every chunk-info record at a
// chunk; index and chunk-info records are as long as their counts say.
// Cost: one pass over the file, unpacking each chunk once more than rosbag does.
// Throws pensight::Error naming the file, the byte offset and what is wrong (never a crash).
#include <cstdint>
#include <filesystem>

namespace pensight {

// rosbag's default chunk is 768 KiB; a chunk holds whole messages, and no message this project
// reads (a camera image) comes near this.
inline constexpr uint64_t kMaxBagChunkBytes = uint64_t{512} << 20;

void check_bag_structure(const std::filesystem::path& bag_file);

}  // namespace pensight
