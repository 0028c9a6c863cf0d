// MAVLink bytes as they arrive from a vehicle's UDP socket (FrameParser, VehicleLink): any bytes
// in any chunking. The first byte picks the chunk size. Every frame the parser returns must decode
// and come back unchanged through encode_frame and a fresh parser; anything else aborts.
#include <algorithm>
#include <cstdlib>
#include <span>

#include "mavlink/frame.h"
#include "mavlink/messages.h"

namespace pensight::mavlink {
namespace {

void check_round_trip(const Frame& f) {
  FrameParser again;
  const auto back = again.feed(encode_frame(f));
  if (back.size() != 1 || back[0].msgid != f.msgid || back[0].payload != f.payload) std::abort();
  if (f.msgid == Heartbeat::kId) unpack<Heartbeat>(f.payload);
  if (f.msgid == Attitude::kId) unpack<Attitude>(f.payload);
  if (f.msgid == SysStatus::kId) unpack<SysStatus>(f.payload);
  if (f.msgid == ScaledPressure::kId) unpack<ScaledPressure>(f.payload);
  if (f.msgid == ScaledPressure2::kId) unpack<ScaledPressure2>(f.payload);
  if (f.msgid == ScaledPressure3::kId) unpack<ScaledPressure3>(f.payload);
}

}  // namespace
}  // namespace pensight::mavlink

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 1) return 0;
  const size_t chunk = size_t{data[0]} + 1;
  const std::span<const uint8_t> bytes(data + 1, size - 1);
  pensight::mavlink::FrameParser parser;
  for (size_t at = 0; at < bytes.size(); at += chunk) {
    for (const auto& f : parser.feed(bytes.subspan(at, std::min(chunk, bytes.size() - at)))) {
      pensight::mavlink::check_round_trip(f);
    }
  }
  return 0;
}
