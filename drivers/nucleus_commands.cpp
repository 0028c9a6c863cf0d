#include "drivers/nucleus_commands.h"

#include <array>
#include <cstdio>
#include <ctime>
#include <string_view>
#include <utility>

#include "core/timing.h"
#include "core/units.h"

namespace pensight::drivers {
namespace {

constexpr std::string_view kPrompt = "Please enter password:", kWelcome = "Welcome to Nortek";
constexpr std::string_view kOk = "OK\r\n", kError = "ERROR\r\n";
// Of text that holds no reply yet, this much is kept: more than any token looked for, so one split
// across reads is still found, while a running Nucleus's records before STOP's reply pass.
constexpr size_t kTextTail = 64;

// SETCLOCKSTR with the host's UTC (the Nucleus's clock need not be set for the records' times,
// which a DeviceClock maps; set, its raw times read as UTC in the dataset's device_time column).
std::string clock_command() {
  const std::time_t t = static_cast<std::time_t>(host_now_ns() / 1'000'000'000);
  std::tm utc{};
  gmtime_r(&t, &utc);
  char text[64];
  std::strftime(text, sizeof text, "SETCLOCKSTR,TIME=\"%Y-%m-%d %H:%M:%S\"\r\n", &utc);
  return text;
}

// The command without its line end, for a message.
std::string_view named(std::string_view command) {
  return command.substr(0, command.find('\r'));
}

constexpr std::array<std::string_view, 3> kBottomTrackModes = {"FAST_ACQ", "AUTO", "CRAWLER"};

}  // namespace

bool is_nucleus_bottom_track_mode(const std::string& mode) {
  for (std::string_view m : kBottomTrackModes) {
    if (mode == m) return true;
  }
  return false;
}

std::string bottom_track_command(const NucleusBottomTrack& settings) {
  std::string command = "SETBT";
  if (!settings.mode.empty()) command += ",MODE=\"" + settings.mode + "\"";
  if (settings.velocity_range_mps > 0) {
    char vr[32];
    std::snprintf(vr, sizeof vr, ",VR=%g", settings.velocity_range_mps);
    command += vr;
  }
  command += settings.water_track ? ",WT=\"ON\"" : ",WT=\"OFF\"";
  return command + ",DS=\"ON\"\r\n";
}

NucleusCommandSession::NucleusCommandSession(NucleusCommandParams params)
    : params_(std::move(params)) {}

std::string NucleusCommandSession::restart(bool password_prompt, int64_t now_ns) {
  password_sent_ = false;
  if (password_prompt) {
    state_ = State::kLogin;
    pending_.clear();
    text_.clear();
    sent_ns_ = now_ns;
    return "";
  }
  return send(State::kStop, "STOP\r\n", now_ns).send;
}

NucleusCommandSession::Step NucleusCommandSession::send(State next, std::string command,
                                                        int64_t now_ns) {
  state_ = next;
  pending_ = std::move(command);
  sent_ns_ = now_ns;
  text_.clear();
  return {pending_, {}};
}

void NucleusCommandSession::fail(std::string what) {
  ++counters_.failures;
  last_error_ = std::move(what);
}

NucleusCommandSession::Step NucleusCommandSession::feed(std::span<const uint8_t> bytes,
                                                        int64_t now_ns) {
  if (state_ == State::kStreaming) return {"", {bytes.begin(), bytes.end()}};
  text_.append(bytes.begin(), bytes.end());
  const size_t ok = text_.find(kOk);
  const bool error = text_.find(kError) != std::string::npos;
  switch (state_) {
    case State::kLogin:
      if (text_.find(kWelcome) != std::string::npos) return send(State::kStop, "STOP\r\n", now_ns);
      if (text_.find(kPrompt) != std::string::npos) {
        if (!password_sent_) {
          password_sent_ = true;
          return send(State::kLogin, params_.password + "\r\n", now_ns);
        }
        fail("the Nucleus refused the password; set dvl.password");
        state_ = State::kRefused;
      }
      break;
    case State::kStop:
      // ERROR too: a Nucleus that was not measuring.
      if (ok != std::string::npos || error) return send(State::kClock, clock_command(), now_ns);
      break;
    case State::kClock:
      if (error) fail("SETCLOCKSTR answered ERROR; the records keep the Nucleus's own clock");
      if (ok != std::string::npos || error) {
        if (params_.bottom_track) {
          return send(State::kBottomTrack, bottom_track_command(*params_.bottom_track), now_ns);
        }
        return send(State::kStart, "START\r\n", now_ns);
      }
      break;
    case State::kBottomTrack:
      if (error) {
        fail(
            "SETBT answered ERROR: the Nucleus measures with its own bottom-track settings; its "
            "GETBTLIM says what it takes (dvl.bottom_track)");
      }
      if (ok != std::string::npos || error) return send(State::kStart, "START\r\n", now_ns);
      break;
    case State::kStart:
      if (ok != std::string::npos) {
        state_ = State::kStreaming;
        pending_.clear();
        ++counters_.starts;
        Step step{"", {text_.begin() + static_cast<std::ptrdiff_t>(ok + kOk.size()), text_.end()}};
        text_.clear();
        return step;
      }
      if (error) {
        fail("START answered ERROR: the Nucleus does not measure; its GETERROR says why");
        state_ = State::kRefused;
      }
      break;
    case State::kStreaming:
    case State::kRefused:
      break;
  }
  if (state_ == State::kRefused) {
    text_.clear();
    return {};
  }
  if (text_.size() > 2 * kTextTail) text_.erase(0, text_.size() - kTextTail);
  if (now_ns - sent_ns_ <= seconds_to_ns(params_.reply_timeout_s)) return {};
  sent_ns_ = now_ns;
  if (pending_.empty()) {
    fail("no password prompt from the Nucleus: is this its command port (9000)?");
    return {};
  }
  fail("no reply to " + (state_ == State::kLogin ? "the password" : std::string(named(pending_))) +
       " from the Nucleus; sent again");
  return {pending_, {}};
}

}  // namespace pensight::drivers
