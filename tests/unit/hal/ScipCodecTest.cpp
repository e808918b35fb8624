#include "hal/scip/ScipCodec.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

namespace carril::hal::scip {
namespace {

std::string enc(std::uint32_t v, int chars) {
  char out[4] = {};
  EXPECT_TRUE(encode(v, chars, out));
  return std::string(out, std::size_t(chars));
}

// Examples from the SCIP 2.0 specification (Hokuyo C-42-03320B, "Data Encoding and Decoding").
TEST(ScipCodec, EncodingsMatchTheSpecExamples) {
  EXPECT_EQ(enc(1234, 2), "CB");
  EXPECT_EQ(enc(5432, 3), "1Dh");
  EXPECT_EQ(enc(16000000, 4), "m2@0");
  std::uint32_t v = 0;
  ASSERT_TRUE(decode("1Dh", 3, v));
  EXPECT_EQ(v, 5432U);
  ASSERT_TRUE(decode("CB", 2, v));
  EXPECT_EQ(v, 1234U);
  ASSERT_TRUE(decode("m2@0", 4, v));
  EXPECT_EQ(v, 16000000U);
}

TEST(ScipCodec, EncodingRefusesWhatDoesNotFitAndDecodingRefusesForeignCharacters) {
  char out[4] = {'x', 'x', 'x', 'x'};
  EXPECT_FALSE(encode(4096, 2, out));  // 2 characters hold 12 bits
  EXPECT_EQ(out[0], 'x');
  EXPECT_TRUE(encode(4095, 2, out));
  EXPECT_EQ(std::string(out, 2), "oo");
  std::uint32_t v = 7;
  EXPECT_FALSE(decode("1D/", 3, v));  // '/' is 0x2F, below the alphabet
  EXPECT_FALSE(decode("1Dp", 3, v));  // 'p' is 0x70, above it
  EXPECT_EQ(v, 7U);
  for (std::uint32_t x : {0U, 1U, 63U, 64U, 262143U}) {
    ASSERT_TRUE(decode(enc(x, 3).c_str(), 3, v));
    EXPECT_EQ(v, x);
  }
}

TEST(ScipCodec, ChecksumsMatchTheSpecExamples) {
  EXPECT_EQ(checksum("1Dh", 3), 'M');  // 0x31 + 0x44 + 0x68 = 0xDD; 0x1D + 0x30
  EXPECT_EQ(checksum("00", 2), 'P');   // status lines "00P" and "99b"
  EXPECT_EQ(checksum("99", 2), 'b');
  // PP reply of a URG-04LX in the spec: "AMIN:44;7", "DMIN:20;4", "DMAX:5600;_".
  EXPECT_EQ(checksum("AMIN:44", 7), '7');
  EXPECT_EQ(checksum("DMIN:20", 7), '4');
  EXPECT_EQ(checksum("DMAX:5600", 9), '_');
  char st[2];
  EXPECT_TRUE(parse_status("99b", 3, st));
  EXPECT_EQ(st[0], '9');
  EXPECT_FALSE(parse_status("99c", 3, st));
  EXPECT_FALSE(parse_status("99", 2, st));
}

TEST(ScipCodec, ParsesCommandsAndNamesTheFirstBadField) {
  const std::string md = "MD0044072501000;scan_1";
  Request r = parse_request(md.data(), md.size());
  EXPECT_EQ(r.cmd, Command::MD);
  EXPECT_EQ(r.start_step, 44);
  EXPECT_EQ(r.end_step, 725);
  EXPECT_EQ(r.cluster, 1);
  EXPECT_EQ(r.interval, 0);
  EXPECT_EQ(r.scans, 0);
  EXPECT_STREQ(r.tag, "scan_1");
  EXPECT_EQ(std::string(r.status, 2), "00");

  auto status_of = [](const std::string& s) {
    const Request q = parse_request(s.data(), s.size());
    return std::string(q.status, 2);
  };
  EXPECT_EQ(status_of("MD00x4072501000"), "01");
  EXPECT_EQ(status_of("MD00440x2501000"), "02");
  EXPECT_EQ(status_of("MD004407250x000"), "03");
  EXPECT_EQ(status_of("MD0044072501x00"), "06");
  EXPECT_EQ(status_of("MD00440725010x0"), "07");
  EXPECT_EQ(status_of("MD0044072501"), "06");  // cut short
  EXPECT_EQ(status_of("MD0725004401000"), "05");
  EXPECT_EQ(status_of("GD0044072501"), "00");
  EXPECT_EQ(status_of("XX"), "0E");
  EXPECT_EQ(status_of("V"), "0E");
  EXPECT_EQ(parse_request("PP", 2).cmd, Command::PP);
}

TEST(ScipCodec, FormatsRequests) {
  char buf[32];
  std::size_t n = format_data_request(Command::MD, 0, 1080, 1, 0, 0, buf, sizeof buf);
  EXPECT_EQ(std::string(buf, n), "MD0000108001000\n");
  n = format_data_request(Command::GD, 44, 725, 3, 0, 0, buf, sizeof buf);
  EXPECT_EQ(std::string(buf, n), "GD0044072503\n");
  EXPECT_EQ(format_data_request(Command::MD, 0, 10000, 1, 0, 0, buf, sizeof buf), 0U);
  EXPECT_EQ(format_data_request(Command::MD, 0, 10, 1, 0, 0, buf, 10), 0U);
  EXPECT_EQ(format_data_request(Command::QT, 0, 10, 1, 0, 0, buf, sizeof buf), 0U);
  n = format_simple_request(Command::QT, buf, sizeof buf);
  EXPECT_EQ(std::string(buf, n), "QT\n");
}

// A scan message as a sensor writes it, with values that span line boundaries.
std::string scan_message(const std::vector<std::uint32_t>& v, int remaining) {
  const std::string cmd = "MD0000" + std::string(4 - std::to_string(v.size() - 1).size(), '0') +
                          std::to_string(v.size() - 1) + "01000";
  const Request r = parse_request(cmd.data(), cmd.size());
  EXPECT_EQ(std::string(r.status, 2), "00");
  std::vector<char> buf(8192);
  ReplyWriter w(buf.data(), buf.size());
  w.echo(r, remaining);
  w.status(kStatusData);
  w.timestamp(123456);
  w.data(v.data(), int(v.size()), 3);
  w.end();
  EXPECT_TRUE(w.ok());
  return std::string(buf.data(), w.size());
}

TEST(ScipCodec, DistanceMessagesRoundTrip) {
  std::vector<std::uint32_t> v(100);
  for (std::size_t i = 0; i < v.size(); ++i) v[i] = std::uint32_t(20 + i * 997 % 30000);
  const std::string msg = scan_message(v, 0);
  // 300 characters: four full lines of 64 and one of 44, each with its sum.
  EXPECT_NE(msg.find("MD0000009901000\n99b\n"), std::string::npos);
  Lines lines;
  ASSERT_TRUE(split_lines(msg.data(), msg.size(), lines));
  EXPECT_EQ(lines.count, 3 + 5);
  EXPECT_EQ(lines.len[3], 65U);
  EXPECT_EQ(lines.len[7], 45U);
  std::vector<std::uint32_t> out(200);
  Distances d;
  ASSERT_EQ(parse_distances(lines, out.data(), nullptr, int(out.size()), d), ReplyError::None);
  EXPECT_TRUE(d.has_data);
  EXPECT_EQ(d.stamp_ms, 123456U);
  ASSERT_EQ(d.count, 100);
  for (int i = 0; i < 100; ++i) EXPECT_EQ(out[std::size_t(i)], v[std::size_t(i)]) << i;
}

TEST(ScipCodec, MalformedDistanceMessagesAreRefused) {
  std::vector<std::uint32_t> v(100, 1234);
  const std::string good = scan_message(v, 0);
  std::vector<std::uint32_t> out(200);
  Distances d;
  auto parse = [&](const std::string& m) {
    Lines lines;
    if (!split_lines(m.data(), m.size(), lines)) return ReplyError::Truncated;
    return parse_distances(lines, out.data(), nullptr, int(out.size()), d);
  };
  ASSERT_EQ(parse(good), ReplyError::None);
  std::string bad = good;
  bad[good.find("99b") + 10] ^= 0x01;  // one data character changed: its line's sum is wrong
  EXPECT_EQ(parse(bad), ReplyError::BadChecksum);
  // A whole data line lost.
  const std::size_t first_data = good.find('\n', good.find("99b") + 4) + 1;
  const std::size_t second = good.find('\n', first_data) + 1;
  bad = good.substr(0, first_data) + good.substr(second);
  EXPECT_EQ(parse(bad), ReplyError::Truncated);
  // Cut in the middle of a line (the message still ends with an empty line).
  bad = good.substr(0, first_data + 10) + "\n\n";
  EXPECT_NE(parse(bad), ReplyError::None);
  // No terminating empty line.
  EXPECT_EQ(parse(good.substr(0, good.size() - 1)), ReplyError::Truncated);
  // Fewer steps in the echo than values sent.
  bad = good;
  bad.replace(bad.find("0099"), 4, "0098");
  EXPECT_EQ(parse(bad), ReplyError::Truncated);
  // An error status ("0E" with its sum "e").
  const std::string err = "MD0000009901000\n0Ee\n\n";
  EXPECT_EQ(parse(err), ReplyError::BadStatus);
  EXPECT_EQ(std::string(d.status, 2), "0E");
  // A buffer too small for the scan.
  Lines lines;
  ASSERT_TRUE(split_lines(good.data(), good.size(), lines));
  EXPECT_EQ(parse_distances(lines, out.data(), nullptr, 50, d), ReplyError::TooLong);
  // The MD acknowledgement carries no data.
  EXPECT_EQ(parse("MD0000009901000\n00P\n\n"), ReplyError::None);
  EXPECT_FALSE(d.has_data);
}

TEST(ScipCodec, MeMessagesCarryIntensities) {
  const std::string cmd = "ME0000000201000";
  const Request r = parse_request(cmd.data(), cmd.size());
  const std::uint32_t ranges[3] = {1000, 2000, 3000};
  char buf[256];
  ReplyWriter w(buf, sizeof buf);
  w.echo(r);
  w.status(kStatusData);
  w.timestamp(5);
  // Range and intensity alternate per step.
  const std::uint32_t pairs[6] = {1000, 11, 2000, 22, 3000, 33};
  w.data(pairs, 6, 3);
  w.end();
  Lines lines;
  ASSERT_TRUE(split_lines(buf, w.size(), lines));
  std::uint32_t out[3], inten[3];
  Distances d;
  ASSERT_EQ(parse_distances(lines, out, inten, 3, d), ReplyError::None);
  for (int i = 0; i < 3; ++i) {
    EXPECT_EQ(out[i], ranges[i]);
    EXPECT_EQ(inten[i], std::uint32_t(11 * (i + 1)));
  }
}

std::string pp_of_spec() {
  // The URG-04LX PP reply printed in the SCIP 2.0 specification. Its ARES sum prints as '/'
  // in the copies found; the sum of "ARES:1024" is 0x5C, a backslash (a yen sign in the
  // Japanese font of the original), and every other sum of the example checks.
  return "PP\n00P\nMODL:URG-04LX(Hokuyo Automatic Co., Ltd.);" +
         std::string(1, checksum("MODL:URG-04LX(Hokuyo Automatic Co., Ltd.)", 41)) +
         "\nDMIN:20;4\nDMAX:5600;_\nARES:1024;\\\nAMIN:44;7\nAMAX:725;o\nAFRT:384;6\n"
         "SCAN:600;e\n\n";
}

TEST(ScipCodec, ParsesThePpReplyOfTheSpec) {
  const std::string pp = pp_of_spec();
  Lines lines;
  ASSERT_TRUE(split_lines(pp.data(), pp.size(), lines));
  Geometry g;
  const char* why = "";
  ASSERT_TRUE(parse_pp(lines, g, why)) << why;
  EXPECT_EQ(g.dmin_mm, 20);
  EXPECT_EQ(g.dmax_mm, 5600);
  EXPECT_EQ(g.ares, 1024);
  EXPECT_EQ(g.amin, 44);
  EXPECT_EQ(g.amax, 725);
  EXPECT_EQ(g.afrt, 384);
  EXPECT_EQ(g.scan_rpm, 600);
  char model[64];
  ASSERT_TRUE(parse_info_reply(lines, Command::PP, "MODL", model, sizeof model, why));
  EXPECT_STREQ(model, "URG-04LX(Hokuyo Automatic Co., Ltd.)");

  std::string bad = pp;
  bad.replace(bad.find("AMIN:44;7"), 9, "AMIN:45;7");
  ASSERT_TRUE(split_lines(bad.data(), bad.size(), lines));
  EXPECT_FALSE(parse_pp(lines, g, why));
  EXPECT_STREQ(why, "PP line malformed or its sum wrong");
  bad = pp;
  bad.erase(bad.find("SCAN"), 11);  // a field missing
  ASSERT_TRUE(split_lines(bad.data(), bad.size(), lines));
  EXPECT_FALSE(parse_pp(lines, g, why));
}

TEST(ScipCodec, InfoLinesWhoseSumIsASemicolon) {
  // Find a value whose sum is ';' and check the line still splits at the right place.
  for (int v = 0; v < 200; ++v) {
    const std::string body = "DMAX:" + std::to_string(v);
    if (checksum(body.data(), body.size()) != ';') continue;
    const std::string line = body + ";;";
    const char *k, *val;
    std::size_t kl, vl;
    ASSERT_TRUE(parse_info(line.data(), line.size(), k, kl, val, vl));
    EXPECT_EQ(std::string(val, vl), std::to_string(v));
    return;
  }
  FAIL() << "no value with sum ';' found";
}

TEST(ScipCodec, RangesMapPerRep117) {
  const float inf = std::numeric_limits<float>::infinity();
  const float nan = std::numeric_limits<float>::quiet_NaN();
  EXPECT_EQ(range_to_wire(1.2344F, 20, 3), 1234U);
  EXPECT_EQ(range_to_wire(inf, 20, 3), kCodeNoReturn);
  EXPECT_EQ(range_to_wire(-inf, 20, 3), kCodeTooClose);
  EXPECT_EQ(range_to_wire(nan, 20, 3), kCodeInvalid);
  EXPECT_EQ(range_to_wire(0.0F, 20, 3), kCodeZero);
  EXPECT_EQ(range_to_wire(0.01F, 20, 3), kCodeTooClose);  // below DMIN
  EXPECT_EQ(range_to_wire(-1.0F, 20, 3), kCodeInvalid);
  EXPECT_EQ(range_to_wire(1e30F, 20, 3), max_encodable(3));  // saturates
  EXPECT_EQ(range_to_wire(5.0F, 20, 2), 4095U);              // MS holds 4095 mm at most
  EXPECT_EQ(wire_to_range(1234, 20), 1.234F);
  EXPECT_EQ(wire_to_range(kCodeNoReturn, 20), inf);
  EXPECT_EQ(wire_to_range(kCodeTooClose, 20), -inf);
  EXPECT_TRUE(std::isnan(wire_to_range(kCodeInvalid, 20)));
  EXPECT_TRUE(std::isnan(wire_to_range(19, 20)));  // another sensor error code
  EXPECT_EQ(wire_to_range(kCodeZero, 20), 0.0F);
  EXPECT_EQ(wire_to_range(60000, 20), 60.0F);  // beyond DMAX: passed through
}

}  // namespace
TEST(ScipCodec, DataOfAWidthTheEncodingHasNotFailsTheWriter) {
  const std::uint32_t values[3] = {1, 2, 3};
  for (const int chars : {0, 5, -1}) {
    char buf[256];
    ReplyWriter w(buf, sizeof buf);
    EXPECT_FALSE(w.data(values, 3, chars)) << chars;
    EXPECT_FALSE(w.ok()) << chars;
    EXPECT_EQ(w.size(), 0U) << chars;
  }
  char buf[256];
  ReplyWriter w(buf, sizeof buf);
  EXPECT_TRUE(w.data(values, 3, 3));
  EXPECT_EQ(w.size(), 11U);  // nine characters, their sum, LF
}

}  // namespace carril::hal::scip
