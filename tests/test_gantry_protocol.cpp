#include <algorithm>
#include <catch2/catch.hpp>
#include <chrono>
#include <cstring>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "gantry_protocol.h"
#include "test_helpers.h"

namespace {

std::vector<uint8_t> FromHex(const std::string& hex) {
  std::vector<uint8_t> out;
  for (std::size_t i = 0; i + 1 < hex.size(); i += 2)
    out.push_back(uint8_t(std::stoi(hex.substr(i, 2), nullptr, 16)));
  return out;
}

int IdOf(const std::string& name) {
  for (int id = 0; id < 256; ++id)
    if (name == gp_message_name(uint8_t(id))) return id;
  return -1;
}

std::vector<gp_message> DecodeAll(const std::vector<uint8_t>& bytes, gp_decoder* d) {
  std::vector<gp_message> out;
  gp_message m;
  for (uint8_t b : bytes)
    if (gp_decoder_push(d, b, &m)) out.push_back(m);
  while (gp_decoder_next(d, &m)) out.push_back(m);
  return out;
}

std::vector<uint8_t> Encode(const gp_message& m) {
  std::vector<uint8_t> out(GP_MAX_FRAME);
  out.resize(gp_encode(&m, out.data(), out.size()));
  return out;
}

struct Golden {
  gp_message message;
  std::vector<uint8_t> frame;
  std::string text;
};

std::vector<Golden> ReadGolden() {
  std::ifstream f(std::string(ACQ_DATA_DIR) + "/../firmware_protocol/golden_vectors.txt");
  std::vector<Golden> out;
  std::string line;
  while (std::getline(f, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream s(line);
    std::string name, fields, hex;
    int sequence;
    s >> name >> sequence >> fields >> hex;
    Golden g{{}, FromHex(hex), line};
    std::memset(&g.message, 0, sizeof g.message);
    g.message.id = uint8_t(IdOf(name));
    g.message.sequence = uint8_t(sequence);
    std::istringstream fs(fields);
    for (std::string kv; std::getline(fs, kv, ',');) {
      const auto eq = kv.find('=');
      REQUIRE(gp_set_field(&g.message, kv.substr(0, eq).c_str(), std::stoll(kv.substr(eq + 1))));
    }
    out.push_back(g);
  }
  return out;
}

}  // namespace

TEST_CASE("CRC-16/CCITT-FALSE check value", "[protocol]") {
  const char* check = "123456789";
  CHECK(gp_crc16(reinterpret_cast<const uint8_t*>(check), 9) == 0x29B1);
}

TEST_CASE("golden vectors: encoded byte for byte, decoded field for field", "[protocol]") {
  const std::vector<Golden> golden = ReadGolden();
  REQUIRE(golden.size() == 24);  // two frames for each of the 12 messages
  for (const Golden& g : golden) {
    INFO(g.text);
    CHECK(Encode(g.message) == g.frame);
    gp_decoder d;
    gp_decoder_init(&d);
    const auto decoded = DecodeAll(g.frame, &d);
    REQUIRE(decoded.size() == 1);
    CHECK(std::memcmp(&decoded[0], &g.message, sizeof(gp_message)) == 0);
  }
}

TEST_CASE("the decoder resyncs after garbage, partial and corrupt frames", "[protocol]") {
  const std::vector<Golden> golden = ReadGolden();
  std::vector<uint8_t> stream = {0x00, 0xA5, 0xA5, 0x13, 0xFF};  // garbage, false syncs
  auto append = [&](const std::vector<uint8_t>& f) {
    stream.insert(stream.end(), f.begin(), f.end());
  };
  append(golden[6].frame);                                         // good
  append({golden[8].frame.begin(), golden[8].frame.begin() + 5});  // partial
  std::vector<uint8_t> corrupt = golden[10].frame;
  corrupt[5] ^= 0x40;
  append(corrupt);           // bad CRC
  append(golden[12].frame);  // good
  std::vector<uint8_t> wrong_length = golden[14].frame;
  wrong_length[1] += 1;
  append(wrong_length);      // length not the id's
  append(golden[16].frame);  // good
  gp_decoder d;
  gp_decoder_init(&d);
  const auto decoded = DecodeAll(stream, &d);
  REQUIRE(decoded.size() == 3);
  CHECK(std::memcmp(&decoded[0], &golden[6].message, sizeof(gp_message)) == 0);
  CHECK(std::memcmp(&decoded[1], &golden[12].message, sizeof(gp_message)) == 0);
  CHECK(std::memcmp(&decoded[2], &golden[16].message, sizeof(gp_message)) == 0);
  CHECK(d.bad_frames > 0);
  CHECK(d.dropped_bytes > 0);
}

TEST_CASE("fuzzing the decoder: no crash, no invented message", "[protocol][fuzz]") {
  // Seeded random streams and mutated golden frames. Every message the decoder emits must be
  // the re-encoding of bytes that are really in the input (CRC and length checked), so
  // garbage can never become a command.
  const std::vector<Golden> golden = ReadGolden();
  std::mt19937_64 rng(20261122);
  std::uniform_int_distribution<int> byte(0, 255), pick(0, int(golden.size()) - 1);
  const auto start = std::chrono::steady_clock::now();
  long inputs = 0, messages = 0, bytes_total = 0;
  for (; inputs < 2000000; ++inputs) {
    std::vector<uint8_t> in;
    const int kind = inputs % 3;
    if (kind == 0) {  // pure noise, biased towards sync bytes
      in.resize(std::size_t(1 + rng() % 64));
      for (auto& b : in) b = rng() % 8 == 0 ? GP_SYNC : uint8_t(byte(rng));
    } else {  // golden frames with flips, truncations and insertions
      for (int f = 0; f < 1 + int(rng() % 3); ++f) {
        std::vector<uint8_t> frame = golden[pick(rng)].frame;
        if (kind == 1 && !frame.empty()) frame[rng() % frame.size()] ^= uint8_t(1 << (rng() % 8));
        if (rng() % 4 == 0) frame.resize(rng() % (frame.size() + 1));
        if (rng() % 4 == 0)
          frame.insert(frame.begin() + long(rng() % (frame.size() + 1)), uint8_t(byte(rng)));
        in.insert(in.end(), frame.begin(), frame.end());
      }
    }
    bytes_total += long(in.size());
    gp_decoder d;
    gp_decoder_init(&d);
    for (const gp_message& m : DecodeAll(in, &d)) {
      ++messages;
      const std::vector<uint8_t> again = Encode(m);
      REQUIRE(!again.empty());
      REQUIRE(std::search(in.begin(), in.end(), again.begin(), again.end()) != in.end());
    }
  }
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  WARN("decoder fuzz: " << inputs << " inputs, " << bytes_total << " bytes, " << messages
                        << " messages decoded, " << seconds << " s");
}

TEST_CASE("the axes and fault bits are declared once, in the protocol's vocabulary", "[protocol]") {
  // The order the per-axis fields of MOVE and STATUS are written in.
  CHECK(GP_AXIS_COUNT == 4);
  CHECK(std::string(gp_axis_name(GP_AXIS_LIGHT_THETA)) == "LIGHT_THETA");
  CHECK(std::string(gp_axis_name(GP_AXIS_CAMERA_PHI)) == "CAMERA_PHI");
  CHECK(std::string(gp_axis_name(4)) == "?");
  // One bit each, distinct, each named and explained; an unknown bit is said to be one.
  std::uint16_t all = 0;
  for (std::uint16_t bit :
       {GP_FAULT_BIT_STALL, GP_FAULT_BIT_LIMIT, GP_FAULT_BIT_LEASE_EXPIRED, GP_FAULT_BIT_ESTOP}) {
    CHECK((all & bit) == 0);
    all |= bit;
    CHECK(std::string(gp_fault_name(bit)) != "?");
    CHECK(std::string(gp_fault_meaning(bit)).size() > 5);
  }
  CHECK(all == 0x0F);
  CHECK(std::string(gp_fault_name(0x100)) == "?");
  CHECK(std::string(gp_fault_meaning(0x100)) == "an unknown fault bit");
}

TEST_CASE("schema hash and sizes come from the table", "[protocol]") {
  CHECK(gp_schema_hash() != 0);
  CHECK(gp_schema_hash() == gp_schema_hash());
  CHECK(gp_payload_size(GP_MOVE) == 4 + 4 * 4);
  CHECK(gp_payload_size(GP_RESULT) == 3);
  CHECK(gp_payload_size(0x00) == -1);
  CHECK(std::string(gp_message_name(GP_ESTOP)) == "ESTOP");
  gp_message m;
  std::memset(&m, 0, sizeof m);
  m.id = 0x00;  // unknown
  uint8_t buf[GP_MAX_FRAME];
  CHECK(gp_encode(&m, buf, sizeof buf) == 0);
  m.id = GP_MOVE;
  CHECK(gp_encode(&m, buf, 10) == 0);  // too small a buffer
  CHECK_FALSE(gp_set_field(&m, "no_such_field", 1));
}
