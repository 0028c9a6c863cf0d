#pragma once
// Camera messages of a bag as the 8-bit grey frames of the dataset (cam0/data/*.png). Colour is
// converted with OpenCV's luma weights, as read_png_grey8 converts a colour PNG, so a colour bag
// gives the frames that the same images stored as colour PNGs would.
#include <cstdint>
#include <span>
#include <string>

#include "core/image.h"

namespace pensight {

// The encodings grey_from_raw_image takes, for messages: "mono8, bgr8, rgb8".
extern const char* const kSupportedImageEncodings;

// A sensor_msgs/Image (its width, height, row step in bytes, encoding and data). `topic` names
// the source in messages. Throws pensight::Error for an encoding other than mono8, bgr8 and rgb8
// (naming it and the supported ones), a step shorter than a row, or data shorter than
// height * step.
ImageU8 grey_from_raw_image(uint32_t width, uint32_t height, uint32_t step,
                            const std::string& encoding, std::span<const uint8_t> data,
                            const std::string& topic);

// A sensor_msgs/CompressedImage holding a JPEG or PNG (its format field, e.g. "jpeg" or
// "bgr8; jpeg compressed bgr8", and data), which must be expect_width x expect_height. The size
// is read from the file's header and checked before decoding, so a header claiming a huge image
// allocates nothing. Throws pensight::Error for another format, a wrong size or data that does
// not decode.
ImageU8 grey_from_compressed_image(const std::string& format, std::span<const uint8_t> data,
                                   int expect_width, int expect_height, const std::string& topic);

}  // namespace pensight
