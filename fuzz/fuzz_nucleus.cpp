// Nortek Nucleus 1000 bytes as they arrive from its TCP data port or serial line (NucleusStream):
// any bytes in any chunking, every packet decoded as each record it may be. The first byte picks
// the chunk size. Every payload must be within the size limit, and the packets' and the skipped
// bytes never more than the input; anything else aborts.
#include <algorithm>
#include <cstdlib>
#include <span>

#include "drivers/nucleus_stream.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace pensight::drivers;
  if (size < 1) return 0;
  const size_t chunk = size_t{data[0]} + 1;
  const std::span<const uint8_t> bytes(data + 1, size - 1);
  NucleusStream stream;
  size_t packet_bytes = 0;
  for (size_t at = 0; at < bytes.size(); at += chunk) {
    for (const NucleusPacket& p :
         stream.feed(bytes.subspan(at, std::min(chunk, bytes.size() - at)))) {
      if (p.payload.size() > kNucleusMaxPayload) std::abort();
      packet_bytes += kNucleusHeaderSize + p.payload.size();
      nucleus_time(p);
      decode_nucleus_track(p);
      decode_nucleus_ahrs(p);
      decode_nucleus_altimeter(p);
    }
  }
  if (packet_bytes + stream.counters().skipped_bytes > bytes.size()) std::abort();
  return 0;
}
