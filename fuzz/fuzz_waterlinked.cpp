// Water Linked DVL bytes as they arrive from its TCP JSON port or its serial line
// (WaterLinkedStream): any bytes in any chunking. The first byte picks the protocol (bit 7) and
// the chunk size; every velocity report is turned into a DvlSample. The stream must account for
// every line it finishes, and a beam's id must index a DvlSample's ranges; anything else aborts.
#include <algorithm>
#include <cstdlib>
#include <span>

#include "drivers/waterlinked.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace pensight::drivers;
  if (size < 1) return 0;
  const auto protocol =
      data[0] & 0x80 ? WaterLinkedStream::Protocol::kSerial : WaterLinkedStream::Protocol::kJson;
  const size_t chunk = size_t{data[0] & 0x7fu} + 1;
  const std::span<const uint8_t> bytes(data + 1, size - 1);
  WaterLinkedStream stream(protocol);
  pensight::DeviceClock clock;
  int64_t arrival_ns = 0;
  for (size_t at = 0; at < bytes.size(); at += chunk) {
    for (const WaterLinkedReport& r :
         stream.feed(bytes.subspan(at, std::min(chunk, bytes.size() - at)))) {
      if (const auto* v = std::get_if<WaterLinkedVelocity>(&r)) {
        to_dvl_sample(*v, Eigen::Matrix3d::Identity(), 0);
        waterlinked_ping_host_ns(*v, arrival_ns += 100'000'000, clock);
      }
    }
  }
  const WaterLinkedCounters& c = stream.counters();
  if (c.reports + c.unknown + c.malformed + c.checksum_failures + c.superseded !=
      stream.line_counters().lines) {
    std::abort();
  }
  return 0;
}
