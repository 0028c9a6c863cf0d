#pragma once
// The head of a map.vdb, checked before OpenVDB parses it. OpenVDB 10's zip and blosc readers
// write a block of the size the file states into a leaf buffer before comparing it with the
// buffer's size (openvdb/io/Compression.cc, bloscFromStream and unzipFromStream), so a crafted
// file overflows them even with a correct checksum. pensight writes maps without zip or blosc
// (active-mask compression only) and reads only such files: the head is parsed here, bounds
// checked, up to the first grid's compression flags. Format: OpenVDB file versions 222-224
// (Archive::readHeader, MetaMap::readMeta, GridDescriptor::read, Archive::readGridCompression).
#include <string_view>

namespace pensight::mapping {

// Throws pensight::Error (the reason, without the file name) unless `bytes` start with an OpenVDB
// header of file version 222-224 holding exactly one grid, a FloatGrid that is not an instance,
// stored without zip or blosc compression. Cost: reads the header and metadata only.
void check_vdb_layout(std::string_view bytes);

}  // namespace pensight::mapping
