// socketlib: deadlines, framing and the protocol codecs, over real loopback
// sockets (socketpair() where no TCP address is needed).
#include <gtest/gtest.h>
#include <sys/socket.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstring>
#include <thread>

#include "socketlib/protocol.h"
#include "socketlib/socketlib.h"

namespace {

struct Pair {
  sl_socket a = SL_SOCKET_INIT, b = SL_SOCKET_INIT;
  Pair() {
    int fds[2];
    EXPECT_EQ(socketpair(AF_UNIX, SOCK_STREAM, 0, fds), 0);
    a.fd = fds[0];
    b.fd = fds[1];
  }
  ~Pair() {
    sl_close(&a);
    sl_close(&b);
  }
};

int64_t in_ms(int ms) { return sl_now_ms() + ms; }

}  // namespace

TEST(ErrorTable, EveryCodeHasADistinctNameAndMessage) {
  EXPECT_STREQ(sl_err_name(SL_ETIMEDOUT), "SL_ETIMEDOUT");
  EXPECT_STREQ(sl_err_name(SL_ECLOSED), "SL_ECLOSED");
  EXPECT_STRNE(sl_strerror(SL_ETIMEDOUT), sl_strerror(SL_ECLOSED));
  EXPECT_STRNE(sl_strerror(SL_ECLOSED), sl_strerror(SL_ETRUNCATED));
  EXPECT_STREQ(sl_strerror(12345), "unknown socketlib error");
}

TEST(Endpoint, ParsesHostAndPort) {
  char host[64];
  int port = 0;
  ASSERT_EQ(sl_parse_endpoint("127.0.0.1:4711", host, sizeof host, &port), SL_OK);
  EXPECT_STREQ(host, "127.0.0.1");
  EXPECT_EQ(port, 4711);
  ASSERT_EQ(sl_parse_endpoint("[::1]:80", host, sizeof host, &port), SL_OK);
  EXPECT_STREQ(host, "::1");
  EXPECT_EQ(sl_parse_endpoint("localhost", host, sizeof host, &port), SL_EADDRESS);
  EXPECT_EQ(sl_parse_endpoint("h:99999", host, sizeof host, &port), SL_EADDRESS);
  EXPECT_EQ(sl_parse_endpoint("h:12x", host, sizeof host, &port), SL_EADDRESS);
  EXPECT_EQ(sl_parse_endpoint(":12", host, sizeof host, &port), SL_EADDRESS);
}

TEST(Header, IsLittleEndianWithFixedOffsets) {
  pcs_header h{PCS_MAGIC, 0x0102, 0x0304, 0x0807060504030201ull, 0x0d0c0b0a};
  uint8_t raw[PCS_HEADER_SIZE];
  pcs_encode_header(&h, raw);
  const uint8_t expected[PCS_HEADER_SIZE] = {'P', 'C', 'S', 'C', 0x02, 0x01, 0x04, 0x03, 1, 2, 3, 4,
                                             5,   6,   7,   8,   0x0a, 0x0b, 0x0c, 0x0d, 0, 0, 0, 0};
  EXPECT_EQ(std::memcmp(raw, expected, sizeof raw), 0);
  pcs_header back{};
  pcs_decode_header(raw, &back);
  EXPECT_EQ(back.step, h.step);
  EXPECT_EQ(back.payload_size, h.payload_size);
}

TEST(Codecs, RoundTripEveryMessage) {
  uint8_t buf[2048];
  pcs_hello hello{PCS_PROTOCOL_VERSION, 0x1234567890abcdefull, 1e-6, 10, {}};
  for (uint32_t i = 0; i < PCS_NONCE_SIZE; ++i) hello.client_nonce[i] = static_cast<uint8_t>(3 * i + 1);
  int n = pcs_encode_hello(&hello, buf, sizeof buf);
  ASSERT_GT(n, 0);
  pcs_hello h2{};
  ASSERT_EQ(pcs_decode_hello(buf, static_cast<uint32_t>(n), &h2), SL_OK);
  EXPECT_EQ(h2.table_hash, hello.table_hash);
  EXPECT_EQ(h2.dt, 1e-6);
  EXPECT_EQ(h2.subcycles, 10u);
  EXPECT_EQ(std::memcmp(h2.client_nonce, hello.client_nonce, PCS_NONCE_SIZE), 0);
  // One byte short or one too many: a layout mismatch, never a silent read.
  EXPECT_EQ(pcs_decode_hello(buf, static_cast<uint32_t>(n - 1), &h2), SL_EMALFORMED);
  EXPECT_EQ(pcs_decode_hello(buf, static_cast<uint32_t>(n + 1), &h2), SL_EMALFORMED);

  const double v[3] = {1.5, -2.25, 1e300};
  n = pcs_encode_values(0.5, 1e-5, v, 3, buf, sizeof buf);
  ASSERT_EQ(n, static_cast<int>(pcs_values_size(3)));
  double t = 0, dt = 0, out[3];
  uint32_t count = 0;
  ASSERT_EQ(pcs_decode_values(buf, static_cast<uint32_t>(n), &t, &dt, out, 3, &count), SL_OK);
  EXPECT_EQ(count, 3u);
  EXPECT_EQ(out[1], -2.25);
  EXPECT_EQ(out[2], 1e300);
  EXPECT_EQ(pcs_decode_values(buf, static_cast<uint32_t>(n), &t, &dt, out, 2, &count), SL_EMALFORMED);
  // A split session's STEP and INPUTS: the importer's thread, then the same
  // layout, 8 bytes more (both sides size their buffers by it: sized for
  // the plain layout, a widest table's frame did not fit).
  n = pcs_encode_tagged_values(0x1234567800000042ull, 0.5, 1e-5, v, 3, buf, sizeof buf);
  ASSERT_EQ(n, static_cast<int>(pcs_tagged_values_size(3)));
  EXPECT_EQ(pcs_tagged_values_size(3), pcs_values_size(3) + 8u);
  uint64_t thread = 0;
  ASSERT_EQ(pcs_decode_tagged_values(buf, static_cast<uint32_t>(n), &thread, &t, &dt, out, 3, &count), SL_OK);
  EXPECT_EQ(thread, 0x1234567800000042ull);
  EXPECT_EQ(count, 3u);
  EXPECT_EQ(out[2], 1e300);
  EXPECT_EQ(pcs_decode_tagged_values(buf, 7, &thread, &t, &dt, out, 3, &count), SL_EMALFORMED);
  EXPECT_EQ(pcs_encode_tagged_values(1, 0.5, 1e-5, v, 3, buf, pcs_tagged_values_size(3) - 1), SL_EOVERSIZE);

  pcs_abort a{7, "because"};
  n = pcs_encode_abort(&a, buf, sizeof buf);
  pcs_abort a2{};
  ASSERT_EQ(pcs_decode_abort(buf, static_cast<uint32_t>(n), &a2), SL_OK);
  EXPECT_STREQ(a2.reason, "because");
  EXPECT_EQ(pcs_encode_abort(&a, buf, 6), SL_EOVERSIZE);

  pcs_challenge ch{};
  for (uint32_t i = 0; i < PCS_NONCE_SIZE; ++i) ch.server_nonce[i] = static_cast<uint8_t>(i);
  n = pcs_encode_challenge(&ch, buf, sizeof buf);
  ASSERT_EQ(n, static_cast<int>(PCS_NONCE_SIZE)) << "a CHALLENGE carries nothing derived from the token";
  pcs_challenge ch2{};
  ASSERT_EQ(pcs_decode_challenge(buf, static_cast<uint32_t>(n), &ch2), SL_OK);
  EXPECT_EQ(std::memcmp(&ch, &ch2, sizeof ch), 0);
  EXPECT_EQ(pcs_decode_challenge(buf, static_cast<uint32_t>(n - 1), &ch2), SL_EMALFORMED);
  pcs_auth au{}, au2{};
  au.client_proof[5] = 42;
  n = pcs_encode_auth(&au, buf, sizeof buf);
  ASSERT_EQ(pcs_decode_auth(buf, static_cast<uint32_t>(n), &au2), SL_OK);
  EXPECT_EQ(au2.client_proof[5], 42);
  EXPECT_EQ(pcs_decode_auth(buf, static_cast<uint32_t>(n + 1), &au2), SL_EMALFORMED);
}

// The proofs are HMAC-SHA-256 as auth.h defines them: checked against values
// computed independently with Python's hmac module (RFC 2104), for
// nonces 0..31 and 32..63 and the table hash 0x1234567890abcdef:
//   hmac.new(b'correct-horse-battery', b'pcs-v5 fe_server\0' + cn + sn + hash_le, sha256)
TEST(Auth, ProofsAreHmacSha256OfTheDocumentedMessage) {
  ASSERT_EQ(pcs_auth_init(), SL_OK);
  uint8_t cn[PCS_NONCE_SIZE], sn[PCS_NONCE_SIZE], proof[PCS_PROOF_SIZE];
  for (uint32_t i = 0; i < PCS_NONCE_SIZE; ++i) cn[i] = static_cast<uint8_t>(i), sn[i] = static_cast<uint8_t>(32 + i);
  auto hex = [](const uint8_t* p) {
    char out[2 * PCS_PROOF_SIZE + 1];
    for (uint32_t i = 0; i < PCS_PROOF_SIZE; ++i) std::snprintf(out + 2 * i, 3, "%02x", p[i]);
    return std::string(out);
  };
  const uint64_t hash = 0x1234567890abcdefull;
  const std::string tok = "correct-horse-battery";
  pcs_auth_proof(tok.data(), tok.size(), PCS_ROLE_SERVER, cn, sn, hash, proof);
  EXPECT_EQ(hex(proof), "d40a22a03c258d654a524c89539992da45b54c7c63176a11b005c75644ed7bc5");
  pcs_auth_proof(tok.data(), tok.size(), PCS_ROLE_HOST, cn, sn, hash, proof);
  EXPECT_EQ(hex(proof), "1d2992c098879ae09e8541561dff9a4f0476dda3b6171a3aed6781be0b52da75");
  EXPECT_TRUE(pcs_auth_check(tok.data(), tok.size(), PCS_ROLE_HOST, cn, sn, hash, proof));
  // Any difference refuses: another role (no reflection), token, nonce, table, or one bit of the proof.
  const std::string other = "correct-horse-batterz";
  EXPECT_FALSE(pcs_auth_check(tok.data(), tok.size(), PCS_ROLE_SERVER, cn, sn, hash, proof));
  EXPECT_FALSE(pcs_auth_check(other.data(), other.size(), PCS_ROLE_HOST, cn, sn, hash, proof));
  EXPECT_FALSE(pcs_auth_check("", 0, PCS_ROLE_HOST, cn, sn, hash, proof));
  EXPECT_FALSE(pcs_auth_check(tok.data(), tok.size(), PCS_ROLE_HOST, sn, cn, hash, proof));
  EXPECT_FALSE(pcs_auth_check(tok.data(), tok.size(), PCS_ROLE_HOST, cn, sn, hash + 1, proof));
  // The key is the bytes given, not a C string: a NUL cannot cut it short
  // (a token "\0" + 30 characters once keyed the HMAC with "").
  const std::string nul_first = std::string(1, '\0') + "0123456789abcdef0123456789abcd";
  uint8_t empty_key[PCS_PROOF_SIZE];
  pcs_auth_proof("", 0, PCS_ROLE_HOST, cn, sn, hash, empty_key);
  EXPECT_EQ(hex(empty_key), "f769d629c259d276a56543634ce167f23fd8ca559546c07657957b4ff3a1b6f1");
  EXPECT_FALSE(pcs_auth_check(nul_first.data(), nul_first.size(), PCS_ROLE_HOST, cn, sn, hash, empty_key));
  proof[31] ^= 1;
  EXPECT_FALSE(pcs_auth_check(tok.data(), tok.size(), PCS_ROLE_HOST, cn, sn, hash, proof));
  // Nonces come from the system's generator: two in a row differ.
  uint8_t a[PCS_NONCE_SIZE], b[PCS_NONCE_SIZE];
  pcs_random_nonce(a);
  pcs_random_nonce(b);
  EXPECT_NE(std::memcmp(a, b, PCS_NONCE_SIZE), 0);
}

TEST(Frames, SendAndReceiveOneFrame) {
  Pair p;
  const uint8_t payload[5] = {1, 2, 3, 4, 5};
  ASSERT_EQ(pcs_send_frame(&p.a, PCS_MSG_STEP, 42, payload, 5, in_ms(1000)), SL_OK);
  pcs_header h{};
  uint8_t buf[16];
  ASSERT_EQ(pcs_recv_frame(&p.b, &h, buf, sizeof buf, in_ms(1000)), SL_OK);
  EXPECT_EQ(h.type, PCS_MSG_STEP);
  EXPECT_EQ(h.step, 42u);
  EXPECT_EQ(h.payload_size, 5u);
  EXPECT_EQ(buf[4], 5);
}

TEST(Frames, ReceiveDeadlineTimesOut) {
  Pair p;
  pcs_header h{};
  uint8_t buf[16];
  auto t0 = std::chrono::steady_clock::now();
  EXPECT_EQ(pcs_recv_frame(&p.b, &h, buf, sizeof buf, in_ms(100)), SL_ETIMEDOUT);
  double waited = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  EXPECT_GE(waited, 0.09);
  EXPECT_LT(waited, 2.0);  // generous: a loaded CI machine, but never a hang
}

TEST(Frames, PeerClosedBeforeAFrameIsClosedNotTruncated) {
  Pair p;
  sl_close(&p.a);
  pcs_header h{};
  uint8_t buf[16];
  EXPECT_EQ(pcs_recv_frame(&p.b, &h, buf, sizeof buf, in_ms(1000)), SL_ECLOSED);
}

TEST(Frames, PeerClosingMidFrameIsTruncated) {
  Pair p;
  uint8_t raw[PCS_HEADER_SIZE];
  pcs_header h{PCS_MAGIC, PCS_PROTOCOL_VERSION, PCS_MSG_STEP, 0, 100};
  pcs_encode_header(&h, raw);
  ASSERT_EQ(sl_send_all(&p.a, raw, 10, in_ms(1000)), SL_OK);  // half a header
  sl_close(&p.a);
  uint8_t buf[128];
  EXPECT_EQ(pcs_recv_frame(&p.b, &h, buf, sizeof buf, in_ms(1000)), SL_ETRUNCATED);
}

TEST(Frames, PayloadCutShortIsTruncated) {
  Pair p;
  uint8_t raw[PCS_HEADER_SIZE + 3];
  pcs_header h{PCS_MAGIC, PCS_PROTOCOL_VERSION, PCS_MSG_STEP, 0, 100};
  pcs_encode_header(&h, raw);
  ASSERT_EQ(sl_send_all(&p.a, raw, sizeof raw, in_ms(1000)), SL_OK);
  sl_close(&p.a);
  uint8_t buf[128];
  EXPECT_EQ(pcs_recv_frame(&p.b, &h, buf, sizeof buf, in_ms(1000)), SL_ETRUNCATED);
}

TEST(Frames, BadMagicAndOversizeAreRefused) {
  Pair p;
  uint8_t raw[PCS_HEADER_SIZE];
  pcs_header h{0xdeadbeef, PCS_PROTOCOL_VERSION, PCS_MSG_STEP, 0, 0};
  pcs_encode_header(&h, raw);
  ASSERT_EQ(sl_send_all(&p.a, raw, sizeof raw, in_ms(1000)), SL_OK);
  uint8_t buf[16];
  EXPECT_EQ(pcs_recv_frame(&p.b, &h, buf, sizeof buf, in_ms(1000)), SL_EBADMAGIC);

  pcs_header big{PCS_MAGIC, PCS_PROTOCOL_VERSION, PCS_MSG_STEP, 0, 0xffffffffu};
  pcs_encode_header(&big, raw);
  ASSERT_EQ(sl_send_all(&p.a, raw, sizeof raw, in_ms(1000)), SL_OK);
  EXPECT_EQ(pcs_recv_frame(&p.b, &h, buf, sizeof buf, in_ms(1000)), SL_EOVERSIZE);
}

TEST(Frames, OtherVersionIsReportedWithTheFrameStillReadable) {
  Pair p;
  uint8_t raw[PCS_HEADER_SIZE + 4] = {};
  pcs_header h{PCS_MAGIC, 99, PCS_MSG_ABORT, 0, 4};
  pcs_encode_header(&h, raw);
  ASSERT_EQ(sl_send_all(&p.a, raw, sizeof raw, in_ms(1000)), SL_OK);
  uint8_t buf[16];
  pcs_header got{};
  EXPECT_EQ(pcs_recv_frame(&p.b, &got, buf, sizeof buf, in_ms(1000)), SL_EVERSION);
  EXPECT_EQ(got.version, 99);
  EXPECT_EQ(got.type, PCS_MSG_ABORT);
}

TEST(Tcp, ConnectIsRefusedUntilTheDeadline) {
  // Bind then close to find a port that nobody listens on.
  sl_socket l = SL_SOCKET_INIT;
  ASSERT_EQ(sl_listen("127.0.0.1", 0, &l), SL_OK);
  int port = sl_local_port(&l);
  sl_close(&l);
  sl_socket c = SL_SOCKET_INIT;
  auto t0 = std::chrono::steady_clock::now();
  EXPECT_EQ(sl_connect("127.0.0.1", port, in_ms(300), &c), SL_EREFUSED);
  double waited = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  EXPECT_GE(waited, 0.25);  // it retried until the deadline
  EXPECT_LT(waited, 3.0);
}

TEST(Tcp, ConnectRetriesUntilTheServerListens) {
  sl_socket l = SL_SOCKET_INIT;
  ASSERT_EQ(sl_listen("127.0.0.1", 0, &l), SL_OK);
  int port = sl_local_port(&l);
  sl_close(&l);
  std::thread server([port] {
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
    sl_socket s = SL_SOCKET_INIT, conn = SL_SOCKET_INIT;
    ASSERT_EQ(sl_listen("127.0.0.1", port, &s), SL_OK);
    EXPECT_EQ(sl_accept(&s, in_ms(3000), &conn), SL_OK);
    sl_close(&conn);
    sl_close(&s);
  });
  sl_socket c = SL_SOCKET_INIT;
  EXPECT_EQ(sl_connect("127.0.0.1", port, in_ms(5000), &c), SL_OK);
  sl_close(&c);
  server.join();
}

TEST(Tcp, AcceptTimesOut) {
  sl_socket l = SL_SOCKET_INIT, conn = SL_SOCKET_INIT;
  ASSERT_EQ(sl_listen("127.0.0.1", 0, &l), SL_OK);
  EXPECT_GT(sl_local_port(&l), 0);
  EXPECT_EQ(sl_accept(&l, in_ms(50), &conn), SL_ETIMEDOUT);
  sl_close(&l);
}
