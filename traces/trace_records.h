// The records of a trace's binary files (docs/traces.md): transactions.bin,
// one record per item per stage, and fragments.bin, one per fragment at a
// depth test or ROP. One definition for the writer (traces/record_files.h)
// and the reader (traces/trace_reader.h): each record lists its fields once,
// in file order (visit_fields), and its encoded size, its little-endian
// encoding and its decoding follow from that list.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <type_traits>

namespace gpusim {

namespace record_codec {

template <typename T>
struct Width {
  static_assert(std::is_arithmetic_v<T>, "a record field is a number or an array of numbers");
  static constexpr size_t bytes = sizeof(T);
};
template <typename T, size_t N>
struct Width<std::array<T, N>> {
  static constexpr size_t bytes = N * Width<T>::bytes;
};

// Sums the fields' widths.
struct Size {
  size_t bytes = 0;
  template <typename T>
  constexpr void operator()(const T&) {
    bytes += Width<T>::bytes;
  }
  constexpr void pad(size_t n) { bytes += n; }
};

// Little endian whatever the host, so the files read the same everywhere.
struct Encoder {
  uint8_t* p;
  template <typename T>
  void operator()(const T& v) {
    if constexpr (std::is_floating_point_v<T>) {
      static_assert(sizeof(T) == 4, "float32 fields");
      uint32_t bits;
      std::memcpy(&bits, &v, 4);
      (*this)(bits);
    } else {
      const auto u = static_cast<std::make_unsigned_t<T>>(v);
      for (size_t i = 0; i < sizeof(T); ++i) *p++ = static_cast<uint8_t>(u >> (8 * i));
    }
  }
  template <typename T, size_t N>
  void operator()(const std::array<T, N>& a) {
    for (const T& v : a) (*this)(v);
  }
  void pad(size_t n) {
    std::memset(p, 0, n);
    p += n;
  }
};

struct Decoder {
  const uint8_t* p;
  template <typename T>
  void operator()(T& v) {
    if constexpr (std::is_floating_point_v<T>) {
      uint32_t bits = 0;
      (*this)(bits);
      std::memcpy(&v, &bits, 4);
    } else {
      std::make_unsigned_t<T> u = 0;
      for (size_t i = 0; i < sizeof(T); ++i) {
        u |= static_cast<std::make_unsigned_t<T>>(static_cast<std::make_unsigned_t<T>>(*p++)
                                                  << (8 * i));
      }
      v = static_cast<T>(u);
    }
  }
  template <typename T, size_t N>
  void operator()(std::array<T, N>& a) {
    for (T& v : a) (*this)(v);
  }
  void pad(size_t n) { p += n; }
};

// visit_fields(v), const or not, for a record whose static visit(record, v)
// lists its fields in file order.
template <typename Record>
struct RecordFields {
  template <typename V>
  constexpr void visit_fields(V& v) const {
    Record::visit(static_cast<const Record&>(*this), v);
  }
  template <typename V>
  constexpr void visit_fields(V& v) {
    Record::visit(static_cast<Record&>(*this), v);
  }
};

}  // namespace record_codec

// One transactions.bin record: an item a stage took in and put out.
struct TransactionRecord : record_codec::RecordFields<TransactionRecord> {
  static constexpr size_t kSize = 48;  // bytes in the file
  enum Kind : uint8_t { work = 0, clear = 1, end_of_frame = 2 };
  // What the item's primitives are at this stage (traces/trace_items.h);
  // none for control tokens and in traces written before the field (the
  // byte was reserved, 0).
  enum PrimKind : uint8_t { prim_none = 0, prim_point = 1, prim_line = 2, prim_triangle = 3 };
  uint64_t cycle_in = 0, cycle_out = 0;
  int64_t prim_first = -1, prim_last = -1;
  uint32_t draw = 0xFFFFFFFFu;
  uint16_t stage = 0;
  uint8_t kind = work;
  uint8_t prim_kind = prim_none;
  int16_t tile_x = -1, tile_y = -1;
  uint32_t count = 1;  // stamps, vertices, ...: what the item holds

  bool carries(int64_t prim) const {
    return prim_first >= 0 && prim_first <= prim && prim <= prim_last;
  }

  // The fields in file order.
  template <typename Self, typename V>
  static constexpr void visit(Self& r, V& v) {
    v(r.cycle_in), v(r.cycle_out), v(r.prim_first), v(r.prim_last), v(r.draw), v(r.stage);
    v(r.kind), v(r.prim_kind), v(r.tile_x), v(r.tile_y), v(r.count);
  }
};

// One fragments.bin record: a fragment at a depth test or a ROP.
struct FragmentRecord : record_codec::RecordFields<FragmentRecord> {
  static constexpr size_t kSize = 48;
  // The site (hw/stage_spec.h, FragmentSite): a fragment depth-tested, or
  // one written to the colour buffer.
  enum Site : uint8_t { at_test = 0, at_write = 1 };
  enum Outcome : uint8_t { failed = 0, passed = 1, passed_test_off = 2, not_written = 3 };
  static constexpr uint8_t written = 1;
  uint64_t cycle = 0;
  int64_t prim = 0;
  uint16_t x = 0, y = 0;
  uint8_t stage = at_test;
  uint8_t unit = 0;
  uint8_t outcome = 0;
  float depth = 0.0f, old_depth = 0.0f;
  std::array<float, 4> value{};  // the stored depth, or the colour written

  // The fields in file order.
  template <typename Self, typename V>
  static constexpr void visit(Self& r, V& v) {
    v(r.cycle), v(r.prim), v(r.x), v(r.y), v(r.stage), v(r.unit), v(r.outcome);
    v.pad(1);
    v(r.depth), v(r.old_depth), v(r.value);
  }
};

// The bytes a record's fields take, from its field list.
template <typename Record>
constexpr size_t encoded_size() {
  Record r{};
  record_codec::Size s;
  r.visit_fields(s);
  return s.bytes;
}
static_assert(encoded_size<TransactionRecord>() == TransactionRecord::kSize,
              "transactions.bin records are 48 bytes (docs/traces.md)");
static_assert(encoded_size<FragmentRecord>() == FragmentRecord::kSize,
              "fragments.bin records are 48 bytes (docs/traces.md)");

// Writes Record::kSize bytes at p.
template <typename Record>
void encode(const Record& r, uint8_t* p) {
  record_codec::Encoder e{p};
  r.visit_fields(e);
}
// Reads one from Record::kSize bytes at p.
template <typename Record>
Record decode(const uint8_t* p) {
  Record r;
  record_codec::Decoder d{p};
  r.visit_fields(d);
  return r;
}

}  // namespace gpusim
