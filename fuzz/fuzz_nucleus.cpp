// Nortek Nucleus 1000 bytes as they arrive from its TCP data port or serial line (NucleusStream),
// and from its command port (NucleusCommandSession first, its clock moving 0.5 s a chunk so that
// replies time out too, then NucleusStream on what it passes on): any bytes in any chunking,
// every packet decoded as each record it may be. The first byte picks the chunk size. The session
// never passes on more than it got, every payload is within the size limit, and the packets' and
// the skipped bytes are never more than the stream got; anything else aborts.
#include <algorithm>
#include <cstdlib>
#include <span>

#include "drivers/nucleus_commands.h"
#include "drivers/nucleus_stream.h"

namespace {

using namespace pensight::drivers;

void read_stream(std::span<const uint8_t> bytes, size_t chunk, bool command_port) {
  NucleusCommandSession session;
  int64_t now_ns = 0;
  session.restart(true, now_ns);
  NucleusStream stream;
  size_t packet_bytes = 0, streamed = 0;
  for (size_t at = 0; at < bytes.size(); at += chunk) {
    const std::span<const uint8_t> part = bytes.subspan(at, std::min(chunk, bytes.size() - at));
    now_ns += 500'000'000;
    const NucleusCommandSession::Step step =
        command_port ? session.feed(part, now_ns)
                     : NucleusCommandSession::Step{"", {part.begin(), part.end()}};
    streamed += step.stream.size();
    if (streamed > at + part.size()) std::abort();
    for (const NucleusPacket& p : stream.feed(step.stream)) {
      if (p.payload.size() > kNucleusMaxPayload) std::abort();
      packet_bytes += kNucleusHeaderSize + p.payload.size();
      nucleus_time(p);
      decode_nucleus_track(p);
      decode_nucleus_ahrs(p);
      decode_nucleus_altimeter(p);
    }
  }
  if (packet_bytes + stream.counters().skipped_bytes > streamed) std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 1) return 0;
  const size_t chunk = size_t{data[0]} + 1;
  const std::span<const uint8_t> bytes(data + 1, size - 1);
  read_stream(bytes, chunk, false);
  read_stream(bytes, chunk, true);
  return 0;
}
