// The Water Linked DVL A50/A125 protocols against Water Linked's own documented examples (the TCP
// JSON API's reports and responses, the serial protocol's sentences and its CRC-8 check value),
// the stream's handling of chunking, line ends and bad lines, the commands, the DvlSample and the
// ping's host time through the DVL's clock.
#include "drivers/waterlinked.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "tests/support/test_seed.h"

namespace pensight::drivers {
namespace {

// The velocity-and-transducer report of Water Linked's TCP JSON API document, on one line as the
// DVL sends it.
const std::string kVelocityReport =
    R"({"time": 106.3935775756836, "vx": -3.713480691658333e-05, "vy": 5.703703573090024e-05, )"
    R"("vz": 2.4990416932269e-05, "fom": 0.00016016385052353144, "covariance": )"
    R"([[2.4471841442164077e-08, -3.3937477272871774e-09, -1.6659699175747278e-09], )"
    R"([-3.3937477272871774e-09, 1.4654466085062268e-08, 4.0409570134514183e-10], )"
    R"([-1.6659699175747278e-09, 4.0409570134514183e-10, 1.5971971523143225e-09]], )"
    R"("altitude": 0.4949815273284912, "transducers": [)"
    R"({"id": 0, "velocity": 0.00010825289791682735, "distance": 0.5568000078201294, )"
    R"("rssi": -30.494251251220703, "nsd": -88.73271179199219, "beam_valid": true}, )"
    R"({"id": 1, "velocity": -1.4719001228513662e-05, "distance": 0.5663999915122986, )"
    R"("rssi": -31.095735549926758, "nsd": -89.5116958618164, "beam_valid": true}, )"
    R"({"id": 2, "velocity": 2.7863150535267778e-05, "distance": 0.537600040435791, )"
    R"("rssi": -27.180519104003906, "nsd": -96.98075103759766, "beam_valid": true}, )"
    R"({"id": 3, "velocity": 1.9419496311456896e-05, "distance": 0.5472000241279602, )"
    R"("rssi": -28.006759643554688, "nsd": -88.32147216796875, "beam_valid": true}], )"
    R"("velocity_valid": true, "status": 0, "tracking_mode": "bottom", "format": "json_v3.2", )"
    R"("type": "velocity", "time_of_validity": 1638191471563017, )"
    R"("time_of_transmission": 1638191471752336})";

const std::string kDeadReckoningReport =
    R"({"ts": 49056.809, "x": 12.43563613697886467, "y": 64.617631152402609587, )"
    R"("z": 1.767641898933798075, "std": 0.001959984190762043, "roll": 0.6173566579818726, )"
    R"("pitch": 0.6173566579818726, "yaw": 0.6173566579818726, "type": "position_local", )"
    R"("status": 0, "format": "json_v3.1"})";

const std::string kGetConfigResponse =
    R"({"response_to":"get_config","success":true,"error_message":"","result":{)"
    R"("speed_of_sound":1475.00,"acoustic_enabled":true,"dark_mode_enabled":false,)"
    R"("mounting_rotation_offset":20.00,"range_mode":"auto","periodic_cycling_enabled":true},)"
    R"("format":"json_v3.1","type":"response"})";

std::span<const uint8_t> bytes_of(const std::string& s) {
  return {reinterpret_cast<const uint8_t*>(s.data()), s.size()};
}

// The report of a line that must be one of type T (a copy: the parse is a temporary).
template <typename T>
T only(const WaterLinkedParse& p) {
  EXPECT_EQ(p.kind, WaterLinkedLine::kReport) << p.error;
  if (!p.report || !std::holds_alternative<T>(*p.report)) {
    ADD_FAILURE() << "not the expected report type";
    return T{};
  }
  return std::get<T>(*p.report);
}

TEST(WaterLinked, Crc8OfTheCheckString) {
  EXPECT_EQ(waterlinked_crc8("123456789"), 0xf4);
}

TEST(WaterLinkedJson, TheDocumentedVelocityReport) {
  const WaterLinkedParse p = parse_waterlinked_json(kVelocityReport);
  const WaterLinkedVelocity v = only<WaterLinkedVelocity>(p);
  EXPECT_FALSE(v.water_track);
  EXPECT_TRUE(v.valid);
  EXPECT_DOUBLE_EQ(v.velocity_mps[0], -3.713480691658333e-05);
  EXPECT_DOUBLE_EQ(v.velocity_mps[2], 2.4990416932269e-05);
  EXPECT_DOUBLE_EQ(v.fom_mps, 0.00016016385052353144);
  EXPECT_DOUBLE_EQ(v.covariance_m2ps2[1], -3.3937477272871774e-09);
  EXPECT_DOUBLE_EQ(v.covariance_m2ps2[8], 1.5971971523143225e-09);
  EXPECT_DOUBLE_EQ(v.altitude_m, 0.4949815273284912);
  ASSERT_EQ(v.beams.size(), 4u);
  EXPECT_EQ(v.beams[2].id, 2);
  EXPECT_DOUBLE_EQ(v.beams[2].distance_m, 0.537600040435791);
  EXPECT_DOUBLE_EQ(v.beams[3].nsd_dbm, -88.32147216796875);
  EXPECT_TRUE(v.beams[1].valid);
  EXPECT_EQ(v.time_of_validity_us, 1638191471563017);
  EXPECT_EQ(v.time_of_transmission_us, 1638191471752336);
  EXPECT_DOUBLE_EQ(v.since_last_report_ms, 106.3935775756836);
  EXPECT_EQ(v.format, "json_v3.2");
}

TEST(WaterLinkedJson, DeadReckoningAndResponses) {
  const WaterLinkedDeadReckoning d =
      only<WaterLinkedDeadReckoning>(parse_waterlinked_json(kDeadReckoningReport));
  EXPECT_DOUBLE_EQ(d.time_s, 49056.809);
  EXPECT_DOUBLE_EQ(d.position_m[1], 64.617631152402609587);
  EXPECT_DOUBLE_EQ(d.yaw_deg, 0.6173566579818726);

  const WaterLinkedResponse r =
      only<WaterLinkedResponse>(parse_waterlinked_json(kGetConfigResponse));
  EXPECT_EQ(r.response_to, "get_config");
  EXPECT_TRUE(r.success);
  EXPECT_NE(r.result.find("\"dark_mode_enabled\":false"), std::string::npos) << r.result;
  const WaterLinkedResponse failed = only<WaterLinkedResponse>(parse_waterlinked_json(
      R"({"response_to":"calibrate_gyro","success":false,"error_message":"busy",)"
      R"("result":null,"format":"json_v3.1","type":"response"})"));
  EXPECT_FALSE(failed.success);
  EXPECT_EQ(failed.error_message, "busy");
  EXPECT_EQ(failed.result, "null");
}

// Older firmware leaves out covariance, times and transducers; a water-track report and an
// unknown key are read; a beam without a return has no distance.
TEST(WaterLinkedJson, OptionalFieldsMayBeMissing) {
  const WaterLinkedVelocity v = only<WaterLinkedVelocity>(parse_waterlinked_json(
      R"({"vx":0.1,"vy":0,"vz":0,"velocity_valid":false,"type":"velocity_water",)"
      R"("new_key":[1,2],"transducers":[{"id":1,"distance":-1,"beam_valid":false}]})"));
  EXPECT_TRUE(v.water_track);
  EXPECT_FALSE(v.valid);
  EXPECT_TRUE(std::isnan(v.covariance_m2ps2[0]));
  EXPECT_FALSE(v.time_of_validity_us);
  ASSERT_EQ(v.beams.size(), 1u);
  EXPECT_FALSE(v.beams[0].valid);
  EXPECT_TRUE(std::isnan(v.beams[0].distance_m));
}

TEST(WaterLinkedJson, BadLinesAreNamedUnknownTypesPassedOver) {
  EXPECT_EQ(parse_waterlinked_json(R"({"type":"imu","x":1})").kind, WaterLinkedLine::kUnknown);
  const std::vector<std::pair<std::string, std::string>> bad = {
      {R"({"vx":0.1,"vy":0,"vz":0,"velocity_valid":tru)", "not JSON"},
      {R"([1,2,3])", "not a JSON object"},
      {R"({"vx":0.1})", "no 'type'"},
      {R"({"vx":0.1,"vz":0,"velocity_valid":true,"type":"velocity"})", "'vy' is missing"},
      {R"({"vx":"fast","vy":0,"vz":0,"velocity_valid":true,"type":"velocity"})",
       "'vx' is not a number"},
      {R"({"vx":0,"vy":0,"vz":0,"velocity_valid":1,"type":"velocity"})",
       "'velocity_valid' is not true or false"},
      {R"({"vx":0,"vy":0,"vz":0,"velocity_valid":true,"covariance":[1,2],"type":"velocity"})",
       "'covariance' is not a 3x3 array of numbers"},
      {R"({"vx":0,"vy":0,"vz":0,"velocity_valid":true,"time_of_validity":9300000000000000,)"
       R"("type":"velocity"})",
       "'time_of_validity' (9300000000000000 us) is outside 0..9223372036854775 us"},
      {R"({"vx":0,"vy":0,"vz":0,"velocity_valid":true,"time_of_transmission":-1,)"
       R"("type":"velocity"})",
       "'time_of_transmission' (-1 us) is outside 0..9223372036854775 us"},
  };
  for (const auto& [line, why] : bad) {
    const WaterLinkedParse p = parse_waterlinked_json(line);
    EXPECT_EQ(p.kind, WaterLinkedLine::kMalformed) << line;
    EXPECT_EQ(p.error, why) << line;
  }
}

TEST(WaterLinkedSerial, TheDocumentedSentences) {
  const WaterLinkedVelocity z = only<WaterLinkedVelocity>(parse_waterlinked_sentence(
      "wrz,0.120,-0.400,2.000,y,1.30,1.855,1e-07;0;1.4;0;1.2;0;0.2;0;1e+09,7,14,123.00,1*50"));
  EXPECT_DOUBLE_EQ(z.velocity_mps[1], -0.4);
  EXPECT_TRUE(z.valid);
  EXPECT_DOUBLE_EQ(z.altitude_m, 1.30);
  EXPECT_DOUBLE_EQ(z.fom_mps, 1.855);
  EXPECT_DOUBLE_EQ(z.covariance_m2ps2[0], 1e-07);
  EXPECT_DOUBLE_EQ(z.covariance_m2ps2[8], 1e+09);
  EXPECT_EQ(z.time_of_validity_us, 7);
  EXPECT_EQ(z.time_of_transmission_us, 14);
  EXPECT_DOUBLE_EQ(z.since_last_report_ms, 123.0);
  EXPECT_EQ(z.status, 1);

  const char* beams[] = {"wru,0,0.070,1.10,-40,-95*9c", "wru,1,-0.500,1.25,-62,-104*f0",
                         "wru,2,2.200,1.40,-56,-98*18", "wru,3,1.800,1.35,-58,-96*a3"};
  const double distances[] = {1.10, 1.25, 1.40, 1.35};
  for (int i = 0; i < 4; ++i) {
    const WaterLinkedBeam b = only<WaterLinkedBeam>(parse_waterlinked_sentence(beams[i]));
    EXPECT_EQ(b.id, i);
    EXPECT_DOUBLE_EQ(b.distance_m, distances[i]);
    EXPECT_TRUE(b.valid);
  }
  const WaterLinkedDeadReckoning p = only<WaterLinkedDeadReckoning>(
      parse_waterlinked_sentence("wrp,49056.809,0.41,0.15,1.23,0.4,53.9,13.0,19.3,0*de"));
  EXPECT_DOUBLE_EQ(p.position_m[2], 1.23);
  EXPECT_DOUBLE_EQ(p.roll_deg, 53.9);
  EXPECT_TRUE(only<WaterLinkedVelocity>(
                  parse_waterlinked_sentence("wrx,112.83,0.007,0.017,0.006,0.000,0.93,y,0*d2"))
                  .valid);
  const WaterLinkedVelocity hot = only<WaterLinkedVelocity>(
      parse_waterlinked_sentence("wrx,1164.94,0.000,0.000,0.000,2.707,-1.00,n,1*39"));
  EXPECT_FALSE(hot.valid);
  EXPECT_EQ(hot.status, 1);
  EXPECT_TRUE(std::isnan(hot.altitude_m));
  EXPECT_TRUE(hot.deprecated_sentence);
  EXPECT_EQ(only<WaterLinkedResponse>(parse_waterlinked_sentence(waterlinked_sentence("wra")))
                .response_to,
            "wra");
  EXPECT_FALSE(
      only<WaterLinkedResponse>(parse_waterlinked_sentence(waterlinked_sentence("wrn"))).success);
  // The deprecated transducer sentence is passed over (wru carries the same, with the beam ids).
  EXPECT_EQ(parse_waterlinked_sentence("wrt,15.00,15.20,14.90,14.20*b1").kind,
            WaterLinkedLine::kUnknown);
}

// The documentation's wrs example carries the wrz example's checksum: computed, it is 7b.
TEST(WaterLinkedSerial, TheDocumentedWrsExampleHasAWrongChecksum) {
  const std::string body =
      "wrs,0.120,-0.400,2.000,y,1.855,1e-07;0;1.4;0;1.2;0;0.2;0;1e+09,7,14,123.00,1";
  const WaterLinkedParse p = parse_waterlinked_sentence(body + "*50");
  EXPECT_EQ(p.kind, WaterLinkedLine::kBadChecksum);
  EXPECT_EQ(p.error, "checksum 50, computed 7b");
  const WaterLinkedVelocity v = only<WaterLinkedVelocity>(parse_waterlinked_sentence(body + "*7b"));
  EXPECT_TRUE(v.water_track);
  EXPECT_TRUE(std::isnan(v.altitude_m));
  EXPECT_DOUBLE_EQ(v.fom_mps, 1.855);
}

TEST(WaterLinkedSerial, BadSentencesAreNamed) {
  const std::vector<std::pair<std::string, std::string>> bad = {
      {"wrz,0.1,0.2", "no checksum ('*xx')"},
      {"wrz,0.1*4", "checksum '4' is not two hex digits"},
      {"hello*00", "not a sentence (starts with 'w')"},
      {waterlinked_sentence("wru,0,0.070,1.10,-40").substr(0, 26), "wru has 4 fields, expected 5"},
      {waterlinked_sentence("wru,7,0.070,1.10,-40,-95"), "id is not 0-3"},
      {waterlinked_sentence("wrx,1,2,3,4,5,6,maybe,0"), "valid is not y or n"},
      {waterlinked_sentence("wrz,0.1,0.2,0.3,y,1.3,0.1,1;2;3,7,14,100,0"),
       "covariance has 3 entries, not 9"},
      {waterlinked_sentence("wrp,1,2,3,nan,5,6,7,8,0"), "z is not a number"},
  };
  for (const auto& [line, why] : bad) {
    const WaterLinkedParse p = parse_waterlinked_sentence(line);
    EXPECT_EQ(p.kind, WaterLinkedLine::kMalformed) << line;
    EXPECT_EQ(p.error, why) << line;
  }
}

// Any chunking and any of the three line ends give the same reports; bad lines are counted and
// the stream goes on; the deprecated wrx of a ping already sent as wrz is dropped.
TEST(WaterLinkedStream, AnyChunkingAndLineEndCountingBadLines) {
  std::mt19937_64 rng(testing::fresh_seed());
  const std::string serial =
      "wrz,0.120,-0.400,2.000,y,1.30,1.855,1e-07;0;1.4;0;1.2;0;0.2;0;1e+09,7,14,123.00,1*50\r\n"
      "wrx,112.83,0.007,0.017,0.006,0.000,0.93,y,0*d2\n"
      "wru,0,0.070,1.10,-40,-95*9c\r"
      "wru,1,-0.500,1.25,-62,-104*f1\n"  // one bit of the checksum flipped
      "garbage\n"
      "wrt,15.00,15.20,14.90,14.20*b1\n"
      "wrp,49056.809,0.41,0.15,1.23,0.4,53.9,13.0,19.3,0*de\n";
  for (int trial = 0; trial < 20; ++trial) {
    WaterLinkedStream s(WaterLinkedStream::Protocol::kSerial);
    std::vector<WaterLinkedReport> all;
    std::uniform_int_distribution<size_t> chunk(1, 40);
    for (size_t at = 0; at < serial.size();) {
      const size_t n = std::min(chunk(rng), serial.size() - at);
      for (auto& r : s.feed(bytes_of(serial).subspan(at, n))) all.push_back(std::move(r));
      at += n;
    }
    ASSERT_EQ(all.size(), 3u);
    EXPECT_TRUE(std::holds_alternative<WaterLinkedVelocity>(all[0]));
    EXPECT_TRUE(std::holds_alternative<WaterLinkedBeam>(all[1]));
    EXPECT_TRUE(std::holds_alternative<WaterLinkedDeadReckoning>(all[2]));
    EXPECT_EQ(s.counters().reports, 3u);
    EXPECT_EQ(s.counters().superseded, 1u);
    EXPECT_EQ(s.counters().checksum_failures, 1u);
    EXPECT_EQ(s.counters().malformed, 1u);
    EXPECT_EQ(s.counters().unknown, 1u);
    EXPECT_EQ(s.last_error(), "not a sentence (starts with 'w')");
  }
  WaterLinkedStream json(WaterLinkedStream::Protocol::kJson);
  const std::string tcp = kVelocityReport + "\r\n{\"type\":\"velocity\"\n" + kDeadReckoningReport +
                          "\n" + kGetConfigResponse.substr(0, 40);
  const std::vector<WaterLinkedReport> r = json.feed(bytes_of(tcp));
  ASSERT_EQ(r.size(), 2u);
  EXPECT_EQ(json.counters().malformed, 1u);
  EXPECT_EQ(json.feed(bytes_of(kGetConfigResponse.substr(40) + "\n")).size(), 1u);
}

TEST(WaterLinkedStream, AnOverlongLineIsDroppedAndTheNextOneRead) {
  WaterLinkedStream s(WaterLinkedStream::Protocol::kJson);
  EXPECT_TRUE(s.feed(bytes_of(std::string(70000, 'x'))).empty());
  EXPECT_EQ(s.feed(bytes_of("yyy\n" + kDeadReckoningReport + "\n")).size(), 1u);
  EXPECT_EQ(s.line_counters().overlong_lines, 1u);
  EXPECT_EQ(s.counters().malformed, 0u);
}

TEST(WaterLinkedCommands, JsonAndSerialCommandsReadBackAsTheDvlDoes) {
  EXPECT_EQ(waterlinked_json_command("get_config"), "{\"command\":\"get_config\"}\n");
  WaterLinkedConfig dark;
  dark.dark_mode_enabled = true;
  EXPECT_EQ(waterlinked_json_set_config(dark),
            "{\"command\":\"set_config\",\"parameters\":{\"dark_mode_enabled\":true}}\n");
  EXPECT_EQ(waterlinked_set_config_sentence(dark), waterlinked_sentence("wcs,,,,y,,"));
  WaterLinkedConfig c;
  c.speed_of_sound_mps = 1450;
  c.acoustic_enabled = false;
  EXPECT_EQ(waterlinked_sentence("wcs,1450,,n,,,").substr(0, 15), "wcs,1450,,n,,,*");
  EXPECT_EQ(waterlinked_set_config_sentence(c), waterlinked_sentence("wcs,1450,,n,,,"));
  // The checksum the DVL computes over a command is the one appended.
  const std::string wcc = waterlinked_sentence("wcc");
  EXPECT_EQ(wcc.back(), '\n');
  EXPECT_EQ(wcc.substr(4, 2), [] {
    char buf[3];
    std::snprintf(buf, sizeof buf, "%02x", waterlinked_crc8("wcc"));
    return std::string(buf);
  }());
}

// The DVL's side (the stand-ins'): the documented report written back reads as the original; a
// report without lock and a beam without return keep no NaN on the wire; commands are answered.
TEST(WaterLinkedJson, ReportsAndRepliesWrittenAsTheDvlReadBack) {
  const WaterLinkedVelocity v = only<WaterLinkedVelocity>(parse_waterlinked_json(kVelocityReport));
  const WaterLinkedVelocity back =
      only<WaterLinkedVelocity>(parse_waterlinked_json(waterlinked_json_velocity(v)));
  EXPECT_EQ(back.velocity_mps, v.velocity_mps);
  EXPECT_EQ(back.valid, v.valid);
  EXPECT_EQ(back.fom_mps, v.fom_mps);
  EXPECT_EQ(back.covariance_m2ps2, v.covariance_m2ps2);
  EXPECT_EQ(back.altitude_m, v.altitude_m);
  ASSERT_EQ(back.beams.size(), v.beams.size());
  for (size_t b = 0; b < v.beams.size(); ++b) {
    EXPECT_EQ(back.beams[b].id, v.beams[b].id);
    EXPECT_EQ(back.beams[b].distance_m, v.beams[b].distance_m);
    EXPECT_EQ(back.beams[b].valid, v.beams[b].valid);
  }
  EXPECT_EQ(back.time_of_validity_us, v.time_of_validity_us);
  EXPECT_EQ(back.time_of_transmission_us, v.time_of_transmission_us);
  EXPECT_EQ(back.format, "json_v3.2");

  WaterLinkedVelocity lost;
  lost.beams.push_back({});
  lost.beams[0].id = 1;
  const std::string line = waterlinked_json_velocity(lost);
  EXPECT_EQ(line.find("null"), std::string::npos) << line;
  const WaterLinkedVelocity lost_back = only<WaterLinkedVelocity>(parse_waterlinked_json(line));
  EXPECT_FALSE(lost_back.valid);
  EXPECT_FALSE(lost_back.beams.at(0).valid);
  EXPECT_EQ(lost_back.format, "json_v3.1");

  EXPECT_EQ(waterlinked_json_command_name(waterlinked_json_set_config({})), "set_config");
  EXPECT_EQ(waterlinked_json_command_name("{\"command\": 3}"), std::nullopt);
  EXPECT_EQ(waterlinked_json_command_name("not json"), std::nullopt);
  const WaterLinkedResponse r = only<WaterLinkedResponse>(
      parse_waterlinked_json(waterlinked_json_response("calibrate_gyro", true)));
  EXPECT_EQ(r.response_to, "calibrate_gyro");
  EXPECT_TRUE(r.success);
}

TEST(WaterLinkedDvlSample, VelocityIntoTheBodyAndBeamsByTheirIds) {
  WaterLinkedVelocity v = only<WaterLinkedVelocity>(parse_waterlinked_json(kVelocityReport));
  v.velocity_mps = {0.3, -0.1, 0.05};
  v.beams[1].valid = false;
  v.beams[1].distance_m = kNaN;
  std::swap(v.beams[0], v.beams[3]);  // the order on the wire does not matter, the id does
  // A DVL looking forward: its Z (down) along the body's x, its X (forward) along the body's -z.
  Eigen::Matrix3d R_B_S;
  R_B_S << 0, 0, 1, 0, 1, 0, -1, 0, 0;
  const DvlSample s = to_dvl_sample(v, R_B_S, 42);
  EXPECT_EQ(s.timestamp_ns, 42);
  EXPECT_TRUE(s.valid);
  EXPECT_TRUE(s.velocity_B_mps.isApprox(Eigen::Vector3d(0.05, -0.1, -0.3)));
  EXPECT_DOUBLE_EQ(s.beam_range_m[0], 0.5568000078201294);
  EXPECT_TRUE(std::isnan(s.beam_range_m[1]));
  EXPECT_DOUBLE_EQ(s.beam_range_m[3], 0.5472000241279602);
  v.valid = false;
  EXPECT_FALSE(to_dvl_sample(v, R_B_S, 42).valid);
}

// Issue 38's clock: the DVL's clock 3 s ahead, each report sent 190 ms after its ping and arriving
// after a transport delay of 0.5 ms plus an exponential jitter of mean 4 ms (Water Linked's
// measured TCP latency: 4 ms mean, 2 ms deviation, 13 ms max). After 10 s of reports at 8 Hz, the
// ping's host time is within 5 ms of the truth; stamped at arrival it would be ~195 ms late.
TEST(WaterLinkedClock, ThePingIsStampedWithin5msThroughTheDvlsClock) {
  std::mt19937_64 rng(testing::fresh_seed());
  std::exponential_distribution<double> jitter_s(1 / 0.004);
  DeviceClock clock;
  const int64_t start_ns = 1'700'000'000'000'000'000, offset_ns = 3'000'000'000;
  double worst_ms = 0, arrival_late_ms = 1e9;
  for (int k = 0; k < 400; ++k) {
    const int64_t ping_ns = start_ns + int64_t{k} * 125'000'000;
    const int64_t sent_ns = ping_ns + 190'000'000;
    const int64_t arrival_ns = sent_ns + 500'000 + static_cast<int64_t>(jitter_s(rng) * 1e9);
    WaterLinkedVelocity v;
    v.time_of_validity_us = (ping_ns + offset_ns) / 1000;
    v.time_of_transmission_us = (sent_ns + offset_ns) / 1000;
    const int64_t stamped = waterlinked_ping_host_ns(v, arrival_ns, clock);
    if (k < 80) continue;  // 10 s
    worst_ms = std::max(worst_ms, std::abs(static_cast<double>(stamped - ping_ns)) * 1e-6);
    arrival_late_ms = std::min(arrival_late_ms, static_cast<double>(arrival_ns - ping_ns) * 1e-6);
  }
  std::printf("ping stamped within %.2f ms (at arrival: >= %.1f ms late)\n", worst_ms,
              arrival_late_ms);
  EXPECT_LE(worst_ms, 5.0);
  EXPECT_GE(arrival_late_ms, 190.0);
  WaterLinkedVelocity old;  // wrx: no times, stamped at arrival
  EXPECT_EQ(waterlinked_ping_host_ns(old, 123, clock), 123);
  WaterLinkedVelocity disagreeing;  // sent before its ping: stamped at arrival
  disagreeing.time_of_validity_us = 2'000'000;
  disagreeing.time_of_transmission_us = 1'000'000;
  EXPECT_EQ(waterlinked_ping_host_ns(disagreeing, 456, clock), 456);
}

}  // namespace
}  // namespace pensight::drivers
