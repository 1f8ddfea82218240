// Packets list their fields once (MatchLib's AUTO_GEN_FIELD_METHODS is the
// model); equality, the printer and the bit width follow from the list.
//
// A packet declares, in field order,
//
//   static constexpr const char* kPacketName = "Stamp";
//   template <typename V>
//   static constexpr void fields(V& v) {
//     using namespace packet_fields;
//     v("x", &Stamp::x, bits(field_bits::kPixel));
//     v("mask", &Stamp::mask, hex);
//     ...
//   }
//
// and `==` and `<<` follow (the templates at the end). A field is a name, a
// pointer to the member and options:
//   bits(n)     its width in hardware (of each element, for an array); without
//               it, the type's: a bool 1 bit, a number its size, an enum what
//               hardware_bits(E) says next to the enum, a packet its fields'
//               sum, a vector nothing (a variable field: the packet's header
//               width counts the rest, the element type has its own width);
//   used(&P::n) an array of which the first `n` elements are in use: only they
//               are compared and printed (hardware still carries them all);
//   hex         printed in hexadecimal;
//   model_only  the model's bookkeeping, not carried by hardware: compared and
//               printed, 0 bits;
//   control     the packet's PacketKind: a control token (any kind but the
//               default, `work`) carries nothing else and prints its kind alone.
// A member pointer of a base class names its fields in a derived packet too.
//
// The printer writes `Name{field value, ...}`; arrays print as (a, b, ...),
// their trailing zeros after the fourth element as "0 xN"; a shared
// primitive prints the primitive, or `none`.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <glm/glm.hpp>
#include <memory>
#include <ostream>
#include <type_traits>
#include <vector>

namespace gpusim {

namespace packet_fields {

struct Bits {
  unsigned n;
};
constexpr Bits bits(unsigned n) {
  return Bits{n};
}
template <typename C, typename N>
struct Used {
  N C::*count;
};
template <typename C, typename N>
constexpr Used<C, N> used(N C::*count) {
  return Used<C, N>{count};
}
struct Hex {};
constexpr Hex hex{};
struct Control {};
constexpr Control control{};
struct ModelOnly {};
constexpr ModelOnly model_only{};

template <typename T, typename = void>
struct HasFields : std::false_type {};
template <typename T>
struct HasFields<T, std::void_t<decltype(T::kPacketName)>> : std::true_type {};

template <typename T>
struct IsVector : std::false_type {};
template <typename T, typename A>
struct IsVector<std::vector<T, A>> : std::true_type {};

// The options a field was declared with.
struct Options {
  unsigned bits = 0;  // 0: the type's
  bool hex = false;
  bool control = false;
  template <typename O>
  constexpr void apply(const O& o) {
    if constexpr (std::is_same_v<O, Bits>) bits = o.n;
    if constexpr (std::is_same_v<O, Hex>) hex = true;
    if constexpr (std::is_same_v<O, Control>) control = true;
  }
};
template <typename... O>
constexpr Options options_of(const O&... o) {
  Options r;
  (r.apply(o), ...);
  return r;
}

template <typename T>
struct IsUsed : std::false_type {};
template <typename C, typename N>
struct IsUsed<Used<C, N>> : std::true_type {};

// Elements of an array field of size N in use on object p: the used() count
// (at most N), or all of them.
template <size_t N, typename P, typename... O>
size_t used_count(const P& p, const O&... o) {
  size_t n = N;
  [[maybe_unused]] const auto take = [&](const auto& opt) {
    if constexpr (IsUsed<std::decay_t<decltype(opt)>>::value) {
      const auto c = static_cast<size_t>(p.*(opt.count));
      n = c < N ? c : N;
    }
  };
  (take(o), ...);
  return n;
}

template <typename T>
struct ArrayTraits : std::false_type {};
template <typename T, size_t N>
struct ArrayTraits<std::array<T, N>> : std::true_type {
  using element = T;
  static constexpr size_t size = N;
};

template <typename T>
struct IsGlmVec : std::false_type {};
template <glm::length_t L, typename T, glm::qualifier Q>
struct IsGlmVec<glm::vec<L, T, Q>> : std::true_type {};

template <typename T>
struct IsSharedPtr : std::false_type {};
template <typename T>
struct IsSharedPtr<std::shared_ptr<T>> : std::true_type {
  using element = std::remove_const_t<T>;
};

// ---- width -----------------------------------------------------------------

template <typename T>
constexpr size_t type_bits();

struct WidthVisitor {
  size_t bits = 0;
  template <typename C, typename M, typename... O>
  constexpr void operator()(const char*, M C::*, const O&... o) {
    constexpr bool carried = !(std::is_same_v<O, ModelOnly> || ...);
    if constexpr (carried && !IsVector<M>::value) {  // a vector is variable: see its element
      const Options opt = options_of(o...);
      if (opt.bits == 0) {
        bits += type_bits<M>();
      } else if constexpr (ArrayTraits<M>::value) {
        bits += ArrayTraits<M>::size * opt.bits;  // bits(n) on an array: n per element
      } else {
        bits += opt.bits;
      }
    }
  }
};

template <typename T>
constexpr size_t type_bits() {
  if constexpr (std::is_same_v<T, bool>) {
    return 1;
  } else if constexpr (std::is_enum_v<T>) {
    return hardware_bits(T{});  // declared next to the enum, found by ADL
  } else if constexpr (std::is_arithmetic_v<T>) {
    return 8 * sizeof(T);
  } else if constexpr (ArrayTraits<T>::value) {
    return ArrayTraits<T>::size * type_bits<typename ArrayTraits<T>::element>();
  } else if constexpr (IsSharedPtr<T>::value) {
    // A primitive shared read-only by the packets that need it travels
    // with each of them as far as the width is concerned.
    return type_bits<typename IsSharedPtr<T>::element>();
  } else if constexpr (HasFields<T>::value) {
    WidthVisitor w;
    T::fields(w);
    return w.bits;
  } else {
    static_assert(IsGlmVec<T>::value && std::is_same_v<typename T::value_type, float>,
                  "a field of unknown width: declare bits(n) or model_only");
    return T::length() * 32;
  }
}

// ---- equality --------------------------------------------------------------

template <typename T>
bool values_equal(const T& a, const T& b) {
  if constexpr (IsSharedPtr<T>::value) {
    return a == b || (a && b && *a == *b);
  } else {
    return a == b;
  }
}

template <typename P>
struct EqualVisitor {
  const P& a;
  const P& b;
  bool equal = true;
  template <typename C, typename M, typename... O>
  void operator()(const char*, M C::*m, const O&... o) {
    if (!equal) return;
    const M& x = a.*m;
    const M& y = b.*m;
    if constexpr (ArrayTraits<M>::value) {
      constexpr size_t N = ArrayTraits<M>::size;
      const size_t na = used_count<N>(a, o...), nb = used_count<N>(b, o...);
      const size_t n = na < nb ? na : nb;  // the counts themselves are fields too
      for (size_t i = 0; i < n && equal; ++i) equal = values_equal(x[i], y[i]);
    } else {
      equal = values_equal(x, y);
    }
  }
};

template <typename P>
bool fields_equal(const P& a, const P& b) {
  EqualVisitor<P> v{a, b};
  P::fields(v);
  return v.equal;
}

// ---- printing --------------------------------------------------------------

template <typename T>
void print_value(std::ostream& os, const T& v, bool hex);

// The first n elements; trailing zeros beyond the first four: "0 xN".
template <typename A>
void print_array(std::ostream& os, const A& a, size_t n, bool hex) {
  size_t shown = n;
  if constexpr (std::is_arithmetic_v<typename ArrayTraits<A>::element>) {
    while (shown > 4 && a[shown - 1] == 0) --shown;
  }
  os << '(';
  for (size_t i = 0; i < shown; ++i) {
    if (i) os << ", ";
    print_value(os, a[i], hex);
  }
  if (shown < n) os << (shown ? ", " : "") << "0 x" << n - shown;
  os << ')';
}

template <typename P>
struct PrintVisitor {
  std::ostream& os;
  const P& p;
  bool first = true;
  bool done = false;  // a control token has printed its kind
  template <typename C, typename M, typename... O>
  void operator()(const char* name, M C::*m, const O&... o) {
    if (done) return;
    const M& v = p.*m;
    os << (first ? "" : ", ") << name << ' ';
    first = false;
    const Options opt = options_of(o...);
    if constexpr (ArrayTraits<M>::value) {
      print_array(os, v, used_count<ArrayTraits<M>::size>(p, o...), opt.hex);
    } else {
      print_value(os, v, opt.hex);
    }
    if (opt.control) done = !(v == M{});
  }
};

template <typename T>
void print_value(std::ostream& os, const T& v, bool hex) {
  if constexpr (std::is_same_v<T, bool>) {
    os << (v ? "true" : "false");
  } else if constexpr (std::is_enum_v<T>) {
    os << v;
  } else if constexpr (std::is_arithmetic_v<T>) {
    // Bytes print as numbers, not characters.
    using Wide = std::conditional_t<std::is_integral_v<T> && sizeof(T) < sizeof(int),
                                    std::conditional_t<std::is_signed_v<T>, int, unsigned>, T>;
    if (hex) {
      os << "0x" << std::hex << static_cast<Wide>(v) << std::dec;
    } else {
      os << static_cast<Wide>(v);
    }
  } else if constexpr (IsSharedPtr<T>::value) {
    if (v) {
      print_value(os, *v, hex);
    } else {
      os << "none";
    }
  } else if constexpr (IsVector<T>::value) {
    os << '[';
    for (size_t i = 0; i < v.size(); ++i) {
      if (i) os << ", ";
      print_value(os, v[i], hex);
    }
    os << ']';
  } else if constexpr (ArrayTraits<T>::value) {
    print_array(os, v, ArrayTraits<T>::size, hex);
  } else if constexpr (IsGlmVec<T>::value) {
    os << '(';
    for (int i = 0; i < T::length(); ++i) os << (i ? ", " : "") << v[i];
    os << ')';
  } else {
    os << v;  // a packet, or a type with its own printer
  }
}

template <typename P>
std::ostream& print_fields(std::ostream& os, const P& p) {
  os << P::kPacketName << '{';
  PrintVisitor<P> v{os, p};
  P::fields(v);
  return os << '}';
}

}  // namespace packet_fields

// Every packet's == and <<, from its field list (found by argument-dependent
// lookup). The field options (bits, used, hex, control, model_only) stay in
// packet_fields: a packet's fields() says `using namespace packet_fields;`.
template <typename P, std::enable_if_t<packet_fields::HasFields<P>::value, int> = 0>
bool operator==(const P& a, const P& b) {
  return packet_fields::fields_equal(a, b);
}
template <typename P, std::enable_if_t<packet_fields::HasFields<P>::value, int> = 0>
std::ostream& operator<<(std::ostream& os, const P& p) {
  return packet_fields::print_fields(os, p);
}

// A packet's width in bits: every field that is not a vector (for a packet
// with vectors, its header; each element type has its own width).
template <typename P>
constexpr size_t packet_bits() {
  return packet_fields::type_bits<P>();
}

}  // namespace gpusim
