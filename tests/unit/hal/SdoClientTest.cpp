#include <gtest/gtest.h>

#include <array>
#include <string>
#include <vector>

#include "hal/can/LoopbackCanBus.hpp"
#include "hal/canopen/SdoClient.hpp"

namespace carril::hal {
namespace {

using Bytes = std::array<std::uint8_t, 8>;
constexpr std::uint8_t kNode = 3;
constexpr TimeNs kMs = 1'000'000;

// Endpoint 0 is the master's port, endpoint 1 a server scripted by each test.
class SdoClientTest : public ::testing::Test {
 protected:
  SdoClientTest() : bus_(LoopbackCanBus::Config{}), client_(bus_.endpoint(0), config()) {}

  static SdoClient::Config config() {
    SdoClient::Config c;
    c.node_id = kNode;
    c.timeout_ns = 50 * kMs;
    return c;
  }

  CanBus& server() { return bus_.endpoint(1); }

  // Every frame the server received since the last call, oldest first.
  std::vector<CanFrame> server_frames() {
    bus_.transfer();
    std::vector<CanFrame> out;
    CanFrame f;
    while (server().receive(f)) out.push_back(f);
    return out;
  }

  // The one request the client sent: checks its identifier and length, returns its bytes.
  Bytes request() {
    const std::vector<CanFrame> frames = server_frames();
    EXPECT_EQ(frames.size(), 1U);
    if (frames.empty()) return {};
    EXPECT_EQ(frames[0].id, 0x600U + kNode);
    EXPECT_FALSE(frames[0].extended);
    EXPECT_EQ(frames[0].len, 8);
    Bytes b;
    for (int i = 0; i < 8; ++i) b[std::size_t(i)] = frames[0].data[i];
    return b;
  }

  // The server answers with `data` (len bytes) from node `node`; the master routes what its
  // port received to the client, as the CANopen master's tick does.
  void reply(const Bytes& data, std::uint8_t len = 8, std::uint8_t node = kNode) {
    CanFrame f;
    f.id = 0x580U + node;
    f.len = len;
    for (int i = 0; i < 8; ++i) f.data[i] = data[std::size_t(i)];
    ASSERT_TRUE(server().send(f));
    bus_.transfer();
    CanFrame in;
    while (bus_.endpoint(0).receive(in)) client_.on_frame(in);
  }

  std::string message() const { return client_.result().message; }

  LoopbackCanBus bus_;
  SdoClient client_;
};

TEST_F(SdoClientTest, DownloadRequestsAreExpeditedWithTheSizeInN) {
  ASSERT_TRUE(client_.start_download(0x6060, 0x00, 0x03, 1));
  EXPECT_EQ(request(), (Bytes{0x2F, 0x60, 0x60, 0x00, 0x03, 0x00, 0x00, 0x00}));
  reply({0x60, 0x60, 0x60, 0x00, 0, 0, 0, 0});

  ASSERT_TRUE(client_.start_download(0x6040, 0x00, 0x000F, 2));
  EXPECT_EQ(request(), (Bytes{0x2B, 0x40, 0x60, 0x00, 0x0F, 0x00, 0x00, 0x00}));
  reply({0x60, 0x40, 0x60, 0x00, 0, 0, 0, 0});

  ASSERT_TRUE(client_.start_download(0x1017, 0x00, 0x12345678, 4));
  EXPECT_EQ(request(), (Bytes{0x23, 0x17, 0x10, 0x00, 0x78, 0x56, 0x34, 0x12}));
  reply({0x60, 0x17, 0x10, 0x00, 0, 0, 0, 0});

  // Only the low size bytes go out: a negative INTEGER8 passed as its two's complement.
  ASSERT_TRUE(client_.start_download(0x2001, 0x02, 0xFFFFFFFEU, 1));
  EXPECT_EQ(request(), (Bytes{0x2F, 0x01, 0x20, 0x02, 0xFE, 0x00, 0x00, 0x00}));
}

TEST_F(SdoClientTest, DownloadRefusesSizesOtherThan124) {
  EXPECT_FALSE(client_.start_download(0x6060, 0, 1, 0));
  EXPECT_FALSE(client_.start_download(0x6060, 0, 1, 3));
  EXPECT_FALSE(client_.start_download(0x6060, 0, 1, 8));
  EXPECT_EQ(client_.result().state, SdoState::Idle);
  EXPECT_TRUE(server_frames().empty());
}

TEST_F(SdoClientTest, UploadRequest) {
  ASSERT_TRUE(client_.start_upload(0x6041, 0x00));
  EXPECT_EQ(request(), (Bytes{0x40, 0x41, 0x60, 0x00, 0x00, 0x00, 0x00, 0x00}));
  EXPECT_TRUE(client_.busy());
  EXPECT_EQ(client_.result().state, SdoState::Busy);
}

TEST_F(SdoClientTest, DownloadDoneOnConfirmation) {
  EXPECT_EQ(client_.result().state, SdoState::Idle);
  ASSERT_TRUE(client_.start_download(0x6060, 0x00, 3, 1));
  request();
  reply({0x60, 0x60, 0x60, 0x00, 0, 0, 0, 0});
  EXPECT_EQ(client_.result().state, SdoState::Done);
  EXPECT_EQ(client_.result().abort_code, 0U);
  EXPECT_EQ(message(), "node 3: SDO download 0x6060:00 = 3 done");
  EXPECT_EQ(client_.protocol_errors(), 0U);
}

TEST_F(SdoClientTest, UploadValuesOf124Bytes) {
  ASSERT_TRUE(client_.start_upload(0x6061, 0x00));
  request();
  reply({0x4F, 0x61, 0x60, 0x00, 0xFD, 0xAA, 0xAA, 0xAA});  // n = 3: bytes 5..7 are padding
  EXPECT_EQ(client_.result().state, SdoState::Done);
  EXPECT_EQ(client_.result().value, 0xFDU);
  EXPECT_EQ(client_.result().size, 1);

  ASSERT_TRUE(client_.start_upload(0x6041, 0x00));
  request();
  reply({0x4B, 0x41, 0x60, 0x00, 0x37, 0x02, 0xAA, 0xAA});
  EXPECT_EQ(client_.result().state, SdoState::Done);
  EXPECT_EQ(client_.result().value, 0x0237U);
  EXPECT_EQ(client_.result().size, 2);
  EXPECT_EQ(message(), "node 3: SDO upload 0x6041:00 = 567 done");

  ASSERT_TRUE(client_.start_upload(0x1018, 0x01));
  request();
  reply({0x43, 0x18, 0x10, 0x01, 0x78, 0x56, 0x34, 0x12});
  EXPECT_EQ(client_.result().state, SdoState::Done);
  EXPECT_EQ(client_.result().value, 0x12345678U);
  EXPECT_EQ(client_.result().size, 4);

  // s = 0: expedited without a size, the whole four bytes count.
  ASSERT_TRUE(client_.start_upload(0x1018, 0x02));
  request();
  reply({0x42, 0x18, 0x10, 0x02, 0x01, 0x02, 0x03, 0x04});
  EXPECT_EQ(client_.result().value, 0x04030201U);
  EXPECT_EQ(client_.result().size, 4);
  EXPECT_EQ(client_.protocol_errors(), 0U);
}

TEST_F(SdoClientTest, ServerAbortNamesCodeAndMeaning) {
  ASSERT_TRUE(client_.start_download(0x6060, 0x00, 3, 1));
  request();
  reply({0x80, 0x60, 0x60, 0x00, 0x30, 0x00, 0x09, 0x06});
  EXPECT_EQ(client_.result().state, SdoState::Aborted);
  EXPECT_EQ(client_.result().abort_code, 0x06090030U);
  EXPECT_EQ(message(),
            "node 3: SDO download 0x6060:00 = 3 aborted: 0x06090030 value range exceeded");
  EXPECT_FALSE(client_.busy());
  EXPECT_TRUE(server_frames().empty());  // the server ended it: no abort back

  ASSERT_TRUE(client_.start_upload(0x2100, 0x05));
  request();
  reply({0x80, 0x00, 0x21, 0x05, 0x11, 0x00, 0x09, 0x06});
  EXPECT_EQ(client_.result().state, SdoState::Aborted);
  EXPECT_EQ(message(), "node 3: SDO upload 0x2100:05 aborted: 0x06090011 sub-index does not exist");
}

TEST_F(SdoClientTest, TimeoutSendsTheClientsOwnAbort) {
  ASSERT_TRUE(client_.start_upload(0x6064, 0x00));
  request();
  client_.poll(1000 * kMs);  // arms the deadline
  client_.poll(1049 * kMs);
  EXPECT_EQ(client_.result().state, SdoState::Busy);
  EXPECT_TRUE(server_frames().empty());
  client_.poll(1050 * kMs);
  EXPECT_EQ(client_.result().state, SdoState::TimedOut);
  EXPECT_EQ(client_.result().abort_code, 0x05040000U);
  EXPECT_EQ(request(), (Bytes{0x80, 0x64, 0x60, 0x00, 0x00, 0x00, 0x04, 0x05}));
  EXPECT_EQ(message(), "node 3: SDO upload 0x6064:00 timed out after 50 ms, sent abort 0x05040000");

  // A late answer after the timeout changes nothing, and a new transfer may start.
  reply({0x43, 0x64, 0x60, 0x00, 1, 2, 3, 4});
  EXPECT_EQ(client_.result().state, SdoState::TimedOut);
  EXPECT_EQ(client_.protocol_errors(), 1U);
  EXPECT_TRUE(client_.start_upload(0x6064, 0x00));
}

TEST_F(SdoClientTest, PollWhileIdleOrDoneSendsNothing) {
  client_.poll(0);
  client_.poll(10'000 * kMs);
  ASSERT_TRUE(client_.start_download(0x6060, 0x00, 3, 1));
  request();
  client_.poll(0);
  reply({0x60, 0x60, 0x60, 0x00, 0, 0, 0, 0});
  client_.poll(10'000 * kMs);
  EXPECT_EQ(client_.result().state, SdoState::Done);
  EXPECT_TRUE(server_frames().empty());
}

TEST_F(SdoClientTest, FramesForOtherNodesAreIgnored) {
  ASSERT_TRUE(client_.start_upload(0x6041, 0x00));
  request();
  reply({0x4B, 0x41, 0x60, 0x00, 0x37, 0x02, 0, 0}, 8, 4);  // node 4's response
  reply({0x4B, 0x41, 0x60, 0x00, 0x37, 0x02, 0, 0}, 8, 2);
  EXPECT_EQ(client_.result().state, SdoState::Busy);
  EXPECT_EQ(client_.protocol_errors(), 0U);  // not ours: not even an error

  CanFrame extended;  // same id but 29-bit: another protocol
  extended.id = 0x580U + kNode;
  extended.extended = true;
  extended.len = 8;
  extended.data[0] = 0x4B;
  extended.data[1] = 0x41;
  extended.data[2] = 0x60;
  client_.on_frame(extended);
  CanFrame error;
  error.id = kCanErrProtocol;
  error.error = true;
  client_.on_frame(error);
  EXPECT_EQ(client_.result().state, SdoState::Busy);
  EXPECT_EQ(client_.protocol_errors(), 0U);
}

TEST_F(SdoClientTest, MalformedResponsesAreCountedNotTrusted) {
  ASSERT_TRUE(client_.start_upload(0x6041, 0x00));
  request();
  reply({0x4B, 0x41, 0x60, 0x00, 0x37, 0x02, 0, 0}, 6);     // too short
  reply({0x4B, 0x41, 0x60, 0x00, 0x37, 0x02, 0, 0}, 0);     // empty
  reply({0x4B, 0x42, 0x60, 0x00, 0x37, 0x02, 0, 0});        // other index
  reply({0x4B, 0x41, 0x60, 0x01, 0x37, 0x02, 0, 0});        // other subindex
  reply({0x80, 0x40, 0x60, 0x00, 0x00, 0x00, 0x02, 0x06});  // abort of another object
  reply({0x60, 0x41, 0x60, 0x00, 0, 0, 0, 0});              // download response to an upload
  reply({0x20, 0x41, 0x60, 0x00, 0, 0, 0, 0});              // segment command
  EXPECT_EQ(client_.result().state, SdoState::Busy);
  EXPECT_EQ(client_.protocol_errors(), 7U);
  EXPECT_TRUE(server_frames().empty());

  // The right answer still lands after the noise.
  reply({0x4B, 0x41, 0x60, 0x00, 0x37, 0x02, 0, 0});
  EXPECT_EQ(client_.result().state, SdoState::Done);
  EXPECT_EQ(client_.result().value, 0x0237U);

  // A download confirmed by an upload response is no confirmation either.
  ASSERT_TRUE(client_.start_download(0x6060, 0x00, 3, 1));
  request();
  reply({0x4F, 0x60, 0x60, 0x00, 3, 0, 0, 0});
  EXPECT_EQ(client_.result().state, SdoState::Busy);
  EXPECT_EQ(client_.protocol_errors(), 8U);
  // Unsolicited responses from our server once idle again are counted too.
  reply({0x60, 0x60, 0x60, 0x00, 0, 0, 0, 0});
  reply({0x60, 0x60, 0x60, 0x00, 0, 0, 0, 0});
  EXPECT_EQ(client_.result().state, SdoState::Done);
  EXPECT_EQ(client_.protocol_errors(), 9U);
}

TEST_F(SdoClientTest, SegmentedResponseIsRejectedWithAbort) {
  ASSERT_TRUE(client_.start_upload(0x1008, 0x00));  // device name: longer than 4 bytes
  request();
  reply({0x41, 0x08, 0x10, 0x00, 0x14, 0x00, 0x00, 0x00});  // e = 0, s = 1: 20 bytes follow
  EXPECT_EQ(client_.result().state, SdoState::Error);
  EXPECT_EQ(client_.result().abort_code, 0x05040001U);
  EXPECT_EQ(request(), (Bytes{0x80, 0x08, 0x10, 0x00, 0x01, 0x00, 0x04, 0x05}));
  EXPECT_EQ(message(),
            "node 3: SDO upload 0x1008:00 failed: segmented transfer not supported, sent abort "
            "0x05040001 command specifier not valid or unknown");
}

TEST_F(SdoClientTest, NewTransferRefusedWhileBusy) {
  ASSERT_TRUE(client_.start_download(0x6060, 0x00, 3, 1));
  EXPECT_FALSE(client_.start_download(0x6060, 0x00, 1, 1));
  EXPECT_FALSE(client_.start_upload(0x6041, 0x00));
  EXPECT_EQ(server_frames().size(), 1U);  // only the first request went out
  reply({0x60, 0x60, 0x60, 0x00, 0, 0, 0, 0});
  EXPECT_EQ(client_.result().state, SdoState::Done);
  EXPECT_EQ(client_.result().value, 3U);  // the refused calls left the transfer alone
  EXPECT_TRUE(client_.start_upload(0x6041, 0x00));
}

TEST(SdoClientConfigTest, InvalidNodeIdStartsNothing) {
  LoopbackCanBus bus(LoopbackCanBus::Config{});
  for (const std::uint8_t id : {std::uint8_t(0), std::uint8_t(128)}) {
    SdoClient::Config c;
    c.node_id = id;
    SdoClient client(bus.endpoint(0), c);
    EXPECT_FALSE(client.start_upload(0x1000, 0));
    EXPECT_FALSE(client.start_download(0x1017, 0, 100, 2));
  }
  bus.transfer();
  CanFrame f;
  EXPECT_FALSE(bus.endpoint(1).receive(f));
}

TEST(SdoClientConfigTest, LongestMessageIsNotCut) {
  LoopbackCanBus bus(LoopbackCanBus::Config{});
  SdoClient::Config c;
  c.node_id = 127;
  SdoClient client(bus.endpoint(0), c);
  ASSERT_TRUE(client.start_download(0xFFFF, 0xFF, 0xFFFFFFFFU, 4));
  CanFrame abort;
  abort.id = 0x580U + 127;
  abort.len = 8;
  const std::uint8_t bytes[8] = {0x80, 0xFF, 0xFF, 0xFF, 0x22, 0x00, 0x00, 0x08};
  for (int i = 0; i < 8; ++i) abort.data[i] = bytes[i];
  client.on_frame(abort);
  EXPECT_EQ(std::string(client.result().message),
            "node 127: SDO download 0xFFFF:FF = 4294967295 aborted: 0x08000022 data cannot be "
            "transferred or stored because of the present device state");
}

TEST(SdoClientConfigTest, RefusedSendIsAnError) {
  LoopbackCanBus bus(LoopbackCanBus::Config{});
  SdoClient::Config c;
  c.node_id = 5;
  SdoClient client(bus.endpoint(0), c);
  bus.force_bus_off(0);
  EXPECT_FALSE(client.start_upload(0x1000, 0));
  EXPECT_EQ(client.result().state, SdoState::Error);
  EXPECT_EQ(std::string(client.result().message),
            "node 5: SDO upload 0x1000:00 failed: request not sent (CAN transmit refused)");
  EXPECT_FALSE(client.busy());
}

}  // namespace
}  // namespace carril::hal
