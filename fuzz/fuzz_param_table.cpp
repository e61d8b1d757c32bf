// libFuzzer harness: the parameter-table loader (param_table.hpp: decode,
// ParameterStore::load), section 6's typed rover geometry included.
//
// Input: one control byte, then the table bytes. The CRC trailer would stop a
// blind fuzzer at the framing checks, so the control byte can patch the
// header's total length and the CRC before decoding; the value checks and the
// section-6 decoder are then reached with arbitrary contents.
//   bit 0: write size into the header's length field (bytes 8..11)
//   bit 1: write the CRC of every byte before the trailer into the trailer
//   bit 2: unused since section 6 is typed and always decoded and validated
//          (it was the extension validator; the seeds keep it)
//
// Checked on every input, besides "no crash, no sanitizer finding":
//   * decode() returns a RejectReason below kRejectReasonCount;
//   * decode() writes `out` only on ok (a sentinel table stays untouched);
//   * an accepted table passes validate(), and a present section 6 holds
//     RoverParams that pass validate_rover_params();
//   * an accepted table encodes to exactly the bytes it came from (the
//     codec is a bijection on valid tables);
//   * ParameterStore::load agrees with decode(), keeps the old table on a
//     rejection and counts it.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <cstring>

#include "sinkwatch/flight/crc32.hpp"
#include "sinkwatch/flight/param_table.hpp"
#include "sinkwatch/flight/rover_geometry.hpp"

namespace sf = sinkwatch::flight;

namespace {

void check(bool condition) {
  if (!condition) {
    std::abort();
  }
}

void put_u32(std::uint8_t* p, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) {
    p[i] = static_cast<std::uint8_t>(v >> (8 * i));
  }
}

bool same_table(const sf::ParameterTable& a, const sf::ParameterTable& b) {
  std::uint8_t ea[sf::kMaxTableBytes];
  std::uint8_t eb[sf::kMaxTableBytes];
  const sf::EncodeResult ra = sf::encode(a, ea, sizeof ea);
  const sf::EncodeResult rb = sf::encode(b, eb, sizeof eb);
  return ra.status == rb.status && ra.size == rb.size && std::memcmp(ea, eb, ra.size) == 0;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1U) {
    return 0;
  }
  const std::uint8_t control = data[0];
  const std::size_t n = size - 1U;
  if (n > sf::kMaxTableBytes + 16U) {
    return 0;  // too_long is checked before any byte is read; longer adds nothing
  }
  // A private copy, so that the patches below and any overread are visible
  // to AddressSanitizer at the exact length.
  auto* bytes = static_cast<std::uint8_t*>(std::malloc(n == 0U ? 1U : n));
  if (n > 0U) {
    std::memcpy(bytes, data + 1, n);
  }
  if (((control & 1U) != 0U) && n >= sf::kTableHeaderBytes) {
    put_u32(bytes + 8, static_cast<std::uint32_t>(n));
  }
  if (((control & 2U) != 0U) && n >= sf::kTableHeaderBytes + sf::kTableCrcBytes) {
    put_u32(bytes + n - sf::kTableCrcBytes, sf::crc32(bytes, n - sf::kTableCrcBytes));
  }

  // decode(): status range, out untouched on rejection.
  const sf::ParameterTable sentinel = sf::eq15_parameter_table();
  sf::ParameterTable out = sentinel;
  const sf::RejectReason r = sf::decode(bytes, n, out);
  check(static_cast<std::uint8_t>(r) < sf::kRejectReasonCount);
  check(r != sf::RejectReason::buffer_too_small);  // an encoder status only
  if (r != sf::RejectReason::ok) {
    check(same_table(out, sentinel));
  } else {
    check(sf::validate(out) == sf::RejectReason::ok);
    if (out.rover_geometry.present) {
      check(sf::validate_rover_params(out.rover_geometry.params) == sf::RoverParamStatus::ok);
    }
    std::uint8_t again[sf::kMaxTableBytes];
    const sf::EncodeResult e = sf::encode(out, again, sizeof again);
    check(e.status == sf::RejectReason::ok);
    check(e.size == n && std::memcmp(again, bytes, n) == 0);
  }

  // ParameterStore::load agrees and keeps the old table on a rejection.
  sf::ParameterStore store;
  const sf::ParameterTable before = store.active();
  const sf::RejectReason loaded = store.load(bytes, n);
  check(loaded == r);
  if (loaded == sf::RejectReason::ok) {
    check(same_table(store.active(), out));
    check(store.active_crc() == sf::crc32(bytes, n - sf::kTableCrcBytes));
    check(store.rejected_count() == 0U);
  } else {
    check(same_table(store.active(), before));
    check(store.rejected_count() == 1U);
    check(store.last_rejection() == loaded);
  }

  // The null buffer is a status, not a crash.
  sf::ParameterTable unused = sentinel;
  check(sf::decode(nullptr, n, unused) == sf::RejectReason::null_buffer);
  std::free(bytes);
  return 0;
}
