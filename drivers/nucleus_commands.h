#pragma once
// The Nortek Nucleus 1000's command interface as a source drives it on each new connection (its
// TCP command port 9000, or its serial line): the password prompt answered (TCP only), STOP (a
// measurement may still run from an earlier session), SETCLOCKSTR with the host's UTC, SETBT where
// bottom-track settings are given, START.
// Every command is a line ending "\r\n", every reply ends "OK\r\n" or "ERROR\r\n" (as Nortek's
// own nucleus_driver drives it); once started, the records follow on the same connection
// (NucleusStream). No sockets here: the caller writes what feed() asks and reads what it returns,
// so the session is tested on its own. Faults are counted, never thrown.
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace pensight::drivers {

inline constexpr int kNucleusCommandPort = 9000;

// SETBT's settings (the keys of Nortek's nucleus_driver set_bt). The bottom-track data stream
// (DS) is always switched on with them: it is what the source reads.
struct NucleusBottomTrack {
  std::string mode;               // MODE: FAST_ACQ, AUTO or CRAWLER; empty: the Nucleus's own
  double velocity_range_mps = 0;  // VR: the largest velocity it measures; 0: the Nucleus's own
  bool water_track = false;       // WT: water-track pings between the bottom-track pings
};

// The modes SETBT takes; `mode` upper-case.
bool is_nucleus_bottom_track_mode(const std::string& mode);
// "SETBT,MODE=...,VR=...,WT=...,DS=\"ON\"\r\n" with the settings given.
std::string bottom_track_command(const NucleusBottomTrack& settings);

struct NucleusCommandParams {
  std::string password = "nortek";                 // Nortek's default
  double reply_timeout_s = 2;                      // a command not answered by then is sent again
  std::optional<NucleusBottomTrack> bottom_track;  // SETBT before START; none: not sent
};

struct NucleusCommandCounters {
  size_t starts = 0;    // measurements started (START answered OK)
  size_t failures = 0;  // a refused password, an ERROR, no reply within reply_timeout_s
};

class NucleusCommandSession {
 public:
  explicit NucleusCommandSession(NucleusCommandParams params = {});

  // A new connection at now_ns: the session starts over. Over TCP the Nucleus asks for the
  // password first; on a serial line there is none. Returns the command to send now ("" for none).
  std::string restart(bool password_prompt, int64_t now_ns);

  struct Step {
    std::string send;             // to write to the Nucleus now ("" for none)
    std::vector<uint8_t> stream;  // the bytes after START's reply: records for NucleusStream
  };
  // Bytes received at now_ns (none: a poll that only checks the reply's time-out).
  Step feed(std::span<const uint8_t> bytes, int64_t now_ns);

  bool streaming() const { return state_ == State::kStreaming; }
  const NucleusCommandCounters& counters() const { return counters_; }
  // The latest failure in words ("" before one).
  const std::string& last_error() const { return last_error_; }

 private:
  enum class State { kLogin, kStop, kClock, kBottomTrack, kStart, kStreaming, kRefused };
  Step send(State next, std::string command, int64_t now_ns);
  void fail(std::string what);

  NucleusCommandParams params_;
  State state_ = State::kLogin;
  std::string text_;     // received since the last command, looked through for its reply
  std::string pending_;  // the command awaiting its reply
  int64_t sent_ns_ = 0;
  bool password_sent_ = false;
  NucleusCommandCounters counters_;
  std::string last_error_;
};

}  // namespace pensight::drivers
