// PNG decoding as the pipeline does it: a camera frame of the calibrated size as 8-bit grey
// (read_png_grey8) and a ground-truth depth image (read_png_u16). The first byte picks the reader
// and whether a size is expected.
#include "fuzz/fuzz_input.h"
#include "pipeline/dataset/png_io.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 1) return 0;
  pensight::fuzz::quiet_log();
  const uint8_t mode = data[0];
  const auto file = pensight::fuzz::write_input(data + 1, size - 1, "frame.png");
  const int w = (mode & 2) != 0 ? 160 : 0, h = (mode & 2) != 0 ? 120 : 0;
  pensight::fuzz::expect_clean_error([&] {
    if ((mode & 1) != 0) {
      pensight::read_png_u16(file, w, h);
    } else {
      pensight::read_png_grey8(file, w, h);
    }
  });
  return 0;
}
