// pensight's frames against node-mavlink (npm), a MAVLink implementation generated from
// common.xml that shares no code with pensight's: it must decode our frames field for field, and
// its frames must be byte for byte ours and decode in our parser.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>

#include "mavlink/frame.h"
#include "mavlink/messages.h"
#include "tests/mavlink/samples.h"

namespace pensight::mavlink {
namespace {

namespace fs = std::filesystem;
using Bytes = std::vector<uint8_t>;
using testing::Fields;

// A frame as node_mavlink.js writes and reads it: "msgid seq sysid compid name=value ...".
struct Line {
  uint32_t msgid = 0;
  int seq = 0, sysid = 0, compid = 0;
  Fields fields;
};

Line parse_line(const std::string& text) {
  std::istringstream in(text);
  Line l;
  in >> l.msgid >> l.seq >> l.sysid >> l.compid;
  for (std::string pair; in >> pair;) {
    const size_t eq = pair.find('=');
    l.fields[pair.substr(0, eq)] = std::strtod(pair.c_str() + eq + 1, nullptr);
  }
  return l;
}

std::string format_line(const Line& l) {
  std::ostringstream out;
  out.precision(17);
  out << l.msgid << ' ' << l.seq << ' ' << l.sysid << ' ' << l.compid;
  for (const auto& [name, value] : l.fields) out << ' ' << name << '=' << value;
  return out.str();
}

Fields decoded_fields(const Frame& f) {
  Fields out;
  testing::for_each_message_type([&]<class M>(M) {
    if (f.msgid == M::kId) out = testing::fields_of(unpack<M>(f.payload));
  });
  return out;
}

// Random messages of every type, as frames (seq, sysid, compid random too) and as lines.
void random_frames(std::mt19937_64& rng, Bytes& bytes, std::vector<Line>& lines) {
  testing::for_each_message_type([&]<class M>(M) {
    for (int i = 0; i < 40; ++i) {
      const M m = testing::random_message<M>(rng);
      const Frame f = make_frame(m, uint8_t(rng()), uint8_t(rng()), uint8_t(rng()));
      const Bytes b = encode_frame(f);
      bytes.insert(bytes.end(), b.begin(), b.end());
      lines.push_back({M::kId, f.seq, f.sysid, f.compid, testing::fields_of(m)});
    }
  });
}

class NodeMavlink : public ::testing::Test {
 protected:
  void SetUp() override {
    const char* src = std::getenv("PENSIGHT_SOURCE_DIR");
    const fs::path dir = src ? fs::path(src) / ".cache" / "node-mavlink" : fs::path();
    if (!fs::exists(dir / "node_modules" / "node-mavlink") ||
        std::system("node --version >/dev/null 2>&1") != 0) {
      GTEST_SKIP() << "node-mavlink check skipped: needs node and `npm install --prefix "
                      ".cache/node-mavlink node-mavlink@2 --ignore-scripts` in the source folder "
                      "(scripts/test.sh does it)";
    }
    script_ = fs::path(src) / "tests" / "mavlink" / "node_mavlink.js";
    modules_ = dir / "node_modules";
    work_ = fs::temp_directory_path() / ("pensight_mavlink_" + std::to_string(::getpid()));
    fs::create_directories(work_);
  }
  void TearDown() override {
    if (!work_.empty()) fs::remove_all(work_);
  }

  // Runs node_mavlink.js `mode` on `input`; returns its output file's bytes.
  std::string run(const std::string& mode, const std::string& input) {
    const fs::path in = work_ / (mode + ".in"), out = work_ / (mode + ".out");
    std::ofstream(in, std::ios::binary) << input;
    const std::string cmd = "NODE_PATH='" + modules_.string() + "' node '" + script_.string() +
                            "' " + mode + " '" + in.string() + "' '" + out.string() + "'";
    EXPECT_EQ(std::system(cmd.c_str()), 0) << cmd;
    std::ifstream f(out, std::ios::binary);
    return {std::istreambuf_iterator<char>(f), {}};
  }

  fs::path script_, modules_, work_;
};

TEST_F(NodeMavlink, DecodesOurFramesFieldForField) {
  std::mt19937_64 rng(pensight::testing::fresh_seed());
  Bytes ours;
  std::vector<Line> sent;
  random_frames(rng, ours, sent);
  std::istringstream out(run("decode", std::string(ours.begin(), ours.end())));
  std::vector<std::string> lines;
  for (std::string line; std::getline(out, line);) lines.push_back(line);
  ASSERT_EQ(lines.size(), sent.size() + 1);
  EXPECT_EQ(lines.back(), "invalid=0 unknown=0") << "node-mavlink rejected frames (CRC_EXTRA?)";
  for (size_t i = 0; i < sent.size(); ++i) {
    const Line got = parse_line(lines[i]);
    EXPECT_EQ(got.msgid, sent[i].msgid);
    EXPECT_EQ(got.seq, sent[i].seq);
    EXPECT_EQ(got.sysid, sent[i].sysid);
    EXPECT_EQ(got.compid, sent[i].compid);
    for (const auto& [name, value] : sent[i].fields) {
      ASSERT_TRUE(got.fields.contains(name)) << lines[i] << " lacks " << name;
      EXPECT_EQ(got.fields.at(name), value) << name << " in " << lines[i];
    }
    for (const auto& [name, value] : got.fields) {
      if (!sent[i].fields.contains(name)) {
        EXPECT_EQ(value, 0) << name << " (not sent by pensight)";
      }
    }
  }
}

TEST_F(NodeMavlink, EncodesTheSameBytesAndOurParserReadsThem) {
  std::mt19937_64 rng(pensight::testing::fresh_seed());
  Bytes ours;
  std::vector<Line> sent;
  random_frames(rng, ours, sent);
  std::string lines;
  for (const Line& l : sent) lines += format_line(l) + "\n";
  const std::string theirs = run("encode", lines);
  EXPECT_EQ(Bytes(theirs.begin(), theirs.end()), ours);
  FrameParser p;
  const auto frames = p.feed(Bytes(theirs.begin(), theirs.end()));
  ASSERT_EQ(frames.size(), sent.size());
  EXPECT_EQ(p.counters().garbage_bytes, 0u);
  for (size_t i = 0; i < frames.size(); ++i) {
    EXPECT_EQ(frames[i].msgid, sent[i].msgid);
    EXPECT_EQ(frames[i].seq, sent[i].seq);
    EXPECT_EQ(frames[i].sysid, sent[i].sysid);
    EXPECT_EQ(decoded_fields(frames[i]), sent[i].fields) << format_line(sent[i]);
  }
}

}  // namespace
}  // namespace pensight::mavlink
