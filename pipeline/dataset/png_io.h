#pragma once
// PNG reading and writing for datasets (OpenCV imgcodecs underneath).
#include <filesystem>

#include "core/image.h"

namespace pensight {

// Any PNG (8/16-bit, grey/colour/alpha) as 8-bit grey: colour is converted with the usual luma
// weights, 16-bit is scaled by 255/65535. Throws pensight::Error when the file is missing or
// unreadable, or when its size is not expect_width x expect_height (pass 0 to accept any size).
ImageU8 read_png_grey8(const std::filesystem::path& file, int expect_width = 0,
                       int expect_height = 0);
// A 16-bit single-channel PNG (e.g. depth in millimetres), unscaled.
ImageU16 read_png_u16(const std::filesystem::path& file, int expect_width = 0,
                      int expect_height = 0);

// Lossless PNG, written whole (temporary name, then rename).
void write_png(const std::filesystem::path& file, const ImageU8& image);
void write_png(const std::filesystem::path& file, const ImageU16& image);
// 8-bit colour (stored in the PNG's own RGB order).
void write_png(const std::filesystem::path& file, const ImageRgb8& image);

}  // namespace pensight
