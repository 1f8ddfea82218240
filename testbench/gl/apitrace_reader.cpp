// apitrace's trace format, read from its own description (docs/replay.md, "The
// trace format"): a snappy container of length-prefixed chunks holding one byte
// stream; in that stream a header and then enter/leave events whose values are
// tagged by a type byte. Signatures (functions, enums, bitmasks, structs,
// backtrace frames) are spelled out the first time their id appears and
// referred to by id afterwards.
#include "testbench/gl/apitrace_reader.h"

#include <snappy.h>
#include <sys/stat.h>

#include <cmath>
#include <cstring>
#include <deque>
#include <iomanip>
#include <limits>
#include <ostream>
#include <sstream>
#include <unordered_set>

#include "hw/input_error.h"

namespace gpusim::gl {

namespace {

// The writer compresses 1 MiB at a time; anything far larger is corruption,
// and refusing it keeps a corrupt length from allocating gigabytes.
constexpr uint64_t kMaxChunk = 64u << 20;
constexpr uint32_t kNewestVersion = 6;

enum Event : int { kEnter = 0, kLeave = 1 };
enum Detail : int { kEnd = 0, kArg = 1, kRet = 2, kThread = 3, kBacktrace = 4, kFlags = 5 };
enum Type : int {
  kNull = 0,
  kFalse,
  kTrue,
  kSInt,
  kUInt,
  kFloat,
  kDouble,
  kString,
  kBlob,
  kEnum,
  kBitmask,
  kArray,
  kStruct,
  kOpaque,
  kRepr,
  kWString
};
constexpr uint64_t kFlagFake = 1;

struct FunctionSig {
  std::string name;
  std::vector<std::string> arg_names;
};
struct EnumSig {
  std::vector<std::pair<std::string, int64_t>> values;
};
struct BitmaskSig {
  std::vector<std::pair<std::string, uint64_t>> flags;
};
struct StructSig {
  std::string name;
  std::vector<std::string> members;
};

// The signature tables are indexed by id; an id met for the first time is
// followed by its definition, as apitrace's parser reads it.
template <typename Sig>
Sig* known(std::vector<std::unique_ptr<Sig>>& table, uint64_t id) {
  if (id >= table.size()) return nullptr;
  return table[id].get();
}
template <typename Sig>
Sig* define(std::vector<std::unique_ptr<Sig>>& table, uint64_t id) {
  if (id >= table.size()) table.resize(id + 1);
  table[id] = std::make_unique<Sig>();
  return table[id].get();
}

void append_utf8(std::string& out, uint32_t c) {
  if (c < 0x80) {
    out += static_cast<char>(c);
  } else if (c < 0x800) {
    out += static_cast<char>(0xC0 | (c >> 6));
    out += static_cast<char>(0x80 | (c & 0x3F));
  } else if (c < 0x10000) {
    out += static_cast<char>(0xE0 | (c >> 12));
    out += static_cast<char>(0x80 | ((c >> 6) & 0x3F));
    out += static_cast<char>(0x80 | (c & 0x3F));
  } else {
    out += static_cast<char>(0xF0 | ((c >> 18) & 0x07));
    out += static_cast<char>(0x80 | ((c >> 12) & 0x3F));
    out += static_cast<char>(0x80 | ((c >> 6) & 0x3F));
    out += static_cast<char>(0x80 | (c & 0x3F));
  }
}

// A bitmask as `apitrace dump` spells it: the flags whose bits are all set, in
// signature order, each clearing its bits; a zero flag only for a zero value;
// what is left over in hex.
std::string bitmask_text(const BitmaskSig& sig, uint64_t value) {
  std::string out;
  bool first = true;
  for (const auto& [name, bits] : sig.flags) {
    if ((bits && (value & bits) == bits) || (!bits && value == 0)) {
      if (!first) out += " | ";
      out += name;
      value &= ~bits;
      first = false;
    }
    if (value == 0) break;
  }
  if (value || first) {
    if (!first) out += " | ";
    std::ostringstream hex;
    hex << "0x" << std::hex << value;
    out += hex.str();
  }
  return out;
}

const char* kind_name(TraceValue::Kind kind) {
  static const char* const names[] = {"null",    "boolean",   "sint",    "uint",        "float32",
                                      "float64", "string",    "blob",    "enumeration", "bitmask",
                                      "array",   "structure", "pointer", "repr"};
  return names[static_cast<int>(kind)];
}

bool is_scalar(TraceValue::Kind kind) {
  using K = TraceValue::Kind;
  return kind == K::boolean || kind == K::sint || kind == K::uint || kind == K::float32 ||
         kind == K::float64 || kind == K::enumeration || kind == K::bitmask;
}

}  // namespace

struct ApitraceReader::State {
  std::string path;
  std::ifstream file;
  uint64_t file_size = 0;
  uint64_t file_pos = 0;  // bytes of the file consumed (magic + whole chunks)

  // The current chunk's decompressed bytes and the read position in them.
  std::string compressed;
  std::string chunk;
  size_t pos = 0;
  uint64_t stream_offset = 0;  // decompressed bytes before the current chunk

  uint32_t version = 0;
  uint32_t semantic_version = 0;
  std::vector<std::pair<std::string, std::string>> properties;

  std::vector<std::unique_ptr<FunctionSig>> functions;
  std::vector<std::unique_ptr<EnumSig>> enums;
  std::vector<std::unique_ptr<BitmaskSig>> bitmasks;
  std::vector<std::unique_ptr<StructSig>> structs;
  std::unordered_set<uint64_t> frames;  // backtrace frame ids already defined

  uint32_t next_number = 0;
  std::deque<TraceCall> pending;  // entered, not yet left, in call order
  bool at_end = false;

  [[noreturn]] void fail(const std::string& what) const { throw InputError(path + ": " + what); }
  [[noreturn]] void corrupt(const std::string& what) const {
    std::ostringstream s;
    s << "corrupt trace at decompressed byte " << stream_offset + pos << ": " << what;
    fail(s.str());
  }

  // Loads the next chunk; false at a clean end of the file.
  bool load_chunk() {
    unsigned char len_bytes[4];
    file.read(reinterpret_cast<char*>(len_bytes), 4);
    const std::streamsize got = file.gcount();
    if (got == 0) return false;
    if (got < 4)
      fail("truncated trace: a chunk length is cut short at file byte " + std::to_string(file_pos));
    const uint64_t length = uint64_t(len_bytes[0]) | uint64_t(len_bytes[1]) << 8 |
                            uint64_t(len_bytes[2]) << 16 | uint64_t(len_bytes[3]) << 24;
    if (length == 0 || length > kMaxChunk)
      fail("corrupt trace: chunk of " + std::to_string(length) + " bytes at file byte " +
           std::to_string(file_pos));
    compressed.resize(length);
    file.read(compressed.data(), static_cast<std::streamsize>(length));
    if (static_cast<uint64_t>(file.gcount()) < length)
      fail("truncated trace: the chunk at file byte " + std::to_string(file_pos) + " has " +
           std::to_string(file.gcount()) + " of its " + std::to_string(length) + " bytes");
    size_t raw = 0;
    if (!snappy::GetUncompressedLength(compressed.data(), length, &raw) || raw > kMaxChunk)
      fail("corrupt trace: the chunk at file byte " + std::to_string(file_pos) +
           " is not valid snappy data");
    stream_offset += chunk.size();
    chunk.resize(raw);
    if (!snappy::RawUncompress(compressed.data(), length, chunk.data()))
      fail("corrupt trace: the chunk at file byte " + std::to_string(file_pos) +
           " is not valid snappy data");
    pos = 0;
    file_pos += 4 + length;
    return true;
  }

  // -1 at the end of the stream (only legal between events).
  int peek_event() {
    while (pos == chunk.size()) {
      if (!load_chunk()) return -1;
    }
    return static_cast<unsigned char>(chunk[pos++]);
  }

  uint8_t byte() {
    while (pos == chunk.size()) {
      if (!load_chunk()) fail("truncated trace: the data ends inside an event");
    }
    return static_cast<uint8_t>(chunk[pos++]);
  }

  void bytes(void* out, size_t n) {
    auto* dst = static_cast<char*>(out);
    while (n) {
      if (pos == chunk.size() && !load_chunk())
        fail("truncated trace: the data ends inside an event");
      const size_t take = std::min(n, chunk.size() - pos);
      std::memcpy(dst, chunk.data() + pos, take);
      pos += take;
      dst += take;
      n -= take;
    }
  }

  void skip(uint64_t n) {
    while (n) {
      if (pos == chunk.size() && !load_chunk())
        fail("truncated trace: the data ends inside an event");
      const uint64_t take = std::min<uint64_t>(n, chunk.size() - pos);
      pos += take;
      n -= take;
    }
  }

  // Little-endian base-128: 7 bits a byte, the top bit set on all but the last.
  uint64_t uint() {
    uint64_t value = 0;
    for (unsigned shift = 0;; shift += 7) {
      const uint8_t c = byte();
      if (shift < 64) value |= uint64_t(c & 0x7F) << shift;
      if (!(c & 0x80)) return value;
      if (shift > 70) corrupt("an integer longer than 10 bytes");
    }
  }

  // A count of elements, which the callers read one at a time and never
  // reserve for: a corrupt count runs into the end of the data (truncated)
  // instead of allocating for it.
  uint64_t count() { return uint(); }

  // Appended chunk by chunk as the data comes, so a corrupt length fails as
  // truncation without first allocating what it claims.
  void string(std::string& out) {
    uint64_t n = uint();
    if (n > kMaxChunk * 16) corrupt("a string of " + std::to_string(n) + " bytes");
    out.clear();
    while (n) {
      if (pos == chunk.size() && !load_chunk())
        fail("truncated trace: the data ends inside an event");
      const size_t take = static_cast<size_t>(std::min<uint64_t>(n, chunk.size() - pos));
      out.append(chunk, pos, take);
      pos += take;
      n -= take;
    }
  }
  std::string string() {
    std::string s;
    string(s);
    return s;
  }

  // An enum signature's values and an enum's value: a type byte, then a uint.
  int64_t sint() {
    const int type = byte();
    if (type == kSInt) return -static_cast<int64_t>(uint());
    if (type == kUInt) return static_cast<int64_t>(uint());
    corrupt("expected an integer, found type " + std::to_string(type));
  }

  void value(TraceValue& v) {
    v = TraceValue();
    using K = TraceValue::Kind;
    const int type = byte();
    switch (type) {
      case kNull:
        return;
      case kFalse:
      case kTrue:
        v.kind = K::boolean;
        v.sint = type == kTrue;
        return;
      case kSInt:
        v.kind = K::sint;
        v.sint = -static_cast<int64_t>(uint());
        return;
      case kUInt:
        v.kind = K::uint;
        v.uint = uint();
        return;
      case kFloat: {
        float f;
        bytes(&f, sizeof f);
        v.kind = K::float32;
        v.real = f;
        return;
      }
      case kDouble:
        bytes(&v.real, sizeof v.real);
        v.kind = K::float64;
        return;
      case kString:
        v.kind = K::string;
        string(v.bytes);
        return;
      case kBlob:
        v.kind = K::blob;
        string(v.bytes);
        return;
      case kEnum: {
        v.kind = K::enumeration;
        const EnumSig* sig = enum_sig();
        if (version >= 3) {
          v.sint = sint();
        } else {
          v.sint = sig->values.front().second;
        }
        for (const auto& [name, value] : sig->values) {
          if (value == v.sint) {
            v.name = name;
            break;
          }
        }
        return;
      }
      case kBitmask: {
        v.kind = K::bitmask;
        const BitmaskSig* sig = bitmask_sig();
        v.uint = uint();
        v.name = bitmask_text(*sig, v.uint);
        return;
      }
      case kArray: {
        v.kind = K::array;
        const uint64_t n = count();
        for (uint64_t i = 0; i < n; ++i) value(v.elements.emplace_back());
        return;
      }
      case kStruct: {
        v.kind = K::structure;
        const StructSig* sig = struct_sig();
        v.name = sig->name;
        v.member_names = sig->members;
        v.elements.resize(sig->members.size());
        for (auto& member : v.elements) value(member);
        return;
      }
      case kOpaque:
        v.kind = K::pointer;
        v.uint = uint();
        return;
      case kRepr:
        // Written human value first; the interface keeps the machine value first.
        v.kind = K::repr;
        v.elements.resize(2);
        value(v.elements[1]);
        value(v.elements[0]);
        return;
      case kWString: {
        v.kind = K::string;
        const uint64_t n = count();
        for (uint64_t i = 0; i < n; ++i) append_utf8(v.bytes, static_cast<uint32_t>(uint()));
        return;
      }
      default:
        corrupt("unknown value type " + std::to_string(type));
    }
  }

  const FunctionSig* function_sig() {
    const uint64_t id = uint();
    if (const FunctionSig* sig = known(functions, id)) return sig;
    FunctionSig* sig = define(functions, id);
    string(sig->name);
    const uint64_t n = count();
    for (uint64_t i = 0; i < n; ++i) sig->arg_names.push_back(string());
    return sig;
  }

  const EnumSig* enum_sig() {
    const uint64_t id = uint();
    if (const EnumSig* sig = known(enums, id)) return sig;
    EnumSig* sig = define(enums, id);
    // Before version 3 a signature held a single name and value.
    const uint64_t n = version >= 3 ? count() : 1;
    for (uint64_t i = 0; i < n; ++i) {
      std::string name = string();
      sig->values.emplace_back(std::move(name), sint());
    }
    if (sig->values.empty()) corrupt("an enum signature with no values");
    return sig;
  }

  const BitmaskSig* bitmask_sig() {
    const uint64_t id = uint();
    if (const BitmaskSig* sig = known(bitmasks, id)) return sig;
    BitmaskSig* sig = define(bitmasks, id);
    const uint64_t n = count();
    for (uint64_t i = 0; i < n; ++i) {
      std::string name = string();
      sig->flags.emplace_back(std::move(name), uint());
    }
    return sig;
  }

  const StructSig* struct_sig() {
    const uint64_t id = uint();
    if (const StructSig* sig = known(structs, id)) return sig;
    StructSig* sig = define(structs, id);
    string(sig->name);
    const uint64_t n = count();
    for (uint64_t i = 0; i < n; ++i) sig->members.push_back(string());
    return sig;
  }

  // Backtraces are read past: the replay has no use for them.
  void backtrace() {
    const uint64_t n = count();
    for (uint64_t i = 0; i < n; ++i) {
      const uint64_t id = uint();
      if (!frames.insert(id).second) continue;
      for (int detail = byte(); detail != 0; detail = byte()) {
        if (detail >= 1 && detail <= 3) {
          skip(uint());  // module, function, file name
        } else if (detail == 4 || detail == 5) {
          uint();  // line number, offset
        } else {
          corrupt("unknown backtrace detail " + std::to_string(detail));
        }
      }
    }
  }

  void details(TraceCall& call) {
    for (;;) {
      const int detail = byte();
      switch (detail) {
        case kEnd:
          return;
        case kArg: {
          const uint64_t index = uint();
          if (index > 4096) corrupt("argument index " + std::to_string(index));
          if (index >= call.args.size()) {
            call.args.resize(index + 1);
            call.arg_names.resize(index + 1);
            call.arg_recorded.resize(index + 1);
          }
          value(call.args[index]);
          call.arg_recorded[index] = true;
          break;
        }
        case kRet:
          value(call.ret);
          call.has_ret = true;
          break;
        case kThread:
          call.thread = static_cast<uint32_t>(uint());
          break;
        case kBacktrace:
          backtrace();
          break;
        case kFlags:
          if (uint() & kFlagFake) call.fake = true;
          break;
        default:
          corrupt("unknown call detail " + std::to_string(detail) + " in call " +
                  std::to_string(call.number) + " " + call.function);
      }
    }
  }

  void enter() {
    TraceCall& call = pending.emplace_back();
    call.thread = version >= 4 ? static_cast<uint32_t>(uint()) : 0;
    const FunctionSig* sig = function_sig();
    call.number = next_number++;
    call.function = sig->name;
    call.arg_names = sig->arg_names;
    call.args.resize(sig->arg_names.size());
    call.arg_recorded.assign(sig->arg_names.size(), false);
    details(call);
  }

  // true with the call completed by this leave event in `out`.
  bool leave(TraceCall& out) {
    const uint64_t number = uint();
    // Usually the call just entered; a call made on another thread meanwhile
    // may sit further up.
    for (auto it = pending.rbegin(); it != pending.rend(); ++it) {
      if (it->number != number) continue;
      details(*it);
      out = std::move(*it);
      pending.erase(std::next(it).base());
      return true;
    }
    // A leave without its enter: apitrace reads past it, and so do we.
    TraceCall stray;
    details(stray);
    return false;
  }
};

ApitraceReader::ApitraceReader(const std::string& path) : m_state(std::make_unique<State>()) {
  State& s = *m_state;
  s.path = path;
  struct stat st {};
  if (stat(path.c_str(), &st) != 0) s.fail(std::string("cannot read: ") + std::strerror(errno));
  if (!S_ISREG(st.st_mode)) s.fail("cannot read: not a regular file");
  s.file_size = static_cast<uint64_t>(st.st_size);
  s.file.open(path, std::ios::binary);
  if (!s.file) s.fail(std::string("cannot read: ") + std::strerror(errno));

  unsigned char magic[2] = {0, 0};
  s.file.read(reinterpret_cast<char*>(magic), 2);
  if (s.file.gcount() < 2) s.fail("not an apitrace trace (shorter than its 2-byte header)");
  if (magic[0] == 0x1F && magic[1] == 0x8B)
    s.fail("a gzip-compressed apitrace trace: only snappy-compressed traces are supported");
  if (magic[0] == 0x28 && magic[1] == 0xB5)
    s.fail("a zstd-compressed apitrace trace: only snappy-compressed traces are supported");
  if (magic[0] != 'a' || magic[1] != 't')
    s.fail("not an apitrace trace (it does not start with the snappy container's 'at')");
  s.file_pos = 2;

  if (s.peek_event() < 0) s.fail("truncated trace: no header");
  --s.pos;
  const uint64_t version = s.uint();
  if (version > kNewestVersion)
    s.fail("unsupported trace format version " + std::to_string(version) +
           " (this reader knows 0 to " + std::to_string(kNewestVersion) + ")");
  s.version = static_cast<uint32_t>(version);
  s.semantic_version = s.version;
  if (s.version >= 6) {
    const uint64_t semantic = s.uint();
    if (semantic > version)
      s.fail("corrupt trace: semantic version " + std::to_string(semantic) +
             " above the format version " + std::to_string(version));
    s.semantic_version = static_cast<uint32_t>(semantic);
    for (;;) {
      std::string name = s.string();
      if (name.empty()) break;
      s.properties.emplace_back(std::move(name), s.string());
    }
  }
}

ApitraceReader::~ApitraceReader() = default;

bool ApitraceReader::next(TraceCall& call) {
  State& s = *m_state;
  if (!s.at_end) {
    for (;;) {
      const int event = s.peek_event();
      if (event == kEnter) {
        s.enter();
      } else if (event == kLeave) {
        if (s.leave(call)) return true;
      } else if (event < 0) {
        s.at_end = true;
        break;
      } else {
        --s.pos;
        s.corrupt("unknown event " + std::to_string(event));
      }
    }
  }
  // The calls still waiting for their leave, in call order, as apitrace ends.
  if (s.pending.empty()) return false;
  call = std::move(s.pending.front());
  s.pending.pop_front();
  call.incomplete = true;
  return true;
}

uint64_t ApitraceReader::bytes_read() const {
  return m_state->file_pos;
}
uint64_t ApitraceReader::file_size() const {
  return m_state->file_size;
}
const std::string& ApitraceReader::path() const {
  return m_state->path;
}
uint32_t ApitraceReader::version() const {
  return m_state->version;
}
uint32_t ApitraceReader::semantic_version() const {
  return m_state->semantic_version;
}
const std::vector<std::pair<std::string, std::string>>& ApitraceReader::properties() const {
  return m_state->properties;
}

// ---------------------------------------------------------------------------
// Values

double TraceValue::to_double() const {
  switch (kind) {
    case Kind::boolean:
    case Kind::sint:
    case Kind::enumeration:
      return static_cast<double>(sint);
    case Kind::uint:
    case Kind::bitmask:
      return static_cast<double>(uint);
    case Kind::float32:
    case Kind::float64:
      return real;
    default:
      throw InputError(std::string("trace value: expected a number, found a ") + kind_name(kind));
  }
}

int64_t TraceValue::to_int() const {
  switch (kind) {
    case Kind::boolean:
    case Kind::sint:
    case Kind::enumeration:
      return sint;
    case Kind::uint:
    case Kind::bitmask:
      return static_cast<int64_t>(uint);
    case Kind::float32:
    case Kind::float64:
      // Truncation toward zero, as a C cast (and apitrace's toSInt) does.
      if (!(std::fabs(real) < 9.2e18))
        throw InputError("trace value: a float out of integer range");
      return static_cast<int64_t>(real);
    default:
      throw InputError(std::string("trace value: expected a number, found a ") + kind_name(kind));
  }
}

uint64_t TraceValue::to_uint() const {
  if (kind == Kind::uint || kind == Kind::bitmask) return uint;
  if (kind == Kind::float32 || kind == Kind::float64) {
    if (!(real > -1.0 && real < 1.8e19))
      throw InputError("trace value: a float out of unsigned range");
    return static_cast<uint64_t>(real);
  }
  if (!is_scalar(kind))
    throw InputError(std::string("trace value: expected a number, found a ") + kind_name(kind));
  return static_cast<uint64_t>(sint);
}

bool TraceValue::operator==(const TraceValue& o) const {
  // Reals compare by their bits, so a NaN equals itself and -0 differs from 0:
  // the same trace must read back as the same values.
  uint64_t a = 0, b = 0;
  std::memcpy(&a, &real, sizeof a);
  std::memcpy(&b, &o.real, sizeof b);
  return kind == o.kind && sint == o.sint && uint == o.uint && a == b && bytes == o.bytes &&
         elements == o.elements && name == o.name && member_names == o.member_names;
}

bool TraceCall::operator==(const TraceCall& o) const {
  return number == o.number && thread == o.thread && function == o.function &&
         arg_names == o.arg_names && args == o.args && ret == o.ret &&
         arg_recorded == o.arg_recorded && has_ret == o.has_ret && fake == o.fake &&
         incomplete == o.incomplete;
}

namespace {

// Strings as `apitrace dump --multiline=false` writes them, including its
// octal escape of other bytes (which repeats the middle digit for the top one).
void print_string(std::ostream& os, const std::string& s) {
  os << '"';
  for (const char ch : s) {
    const unsigned c = static_cast<unsigned char>(ch);
    if (c == '"') {
      os << "\\\"";
    } else if (c == '\\') {
      os << "\\\\";
    } else if ((c >= 0x20 && c <= 0x7E) || c == '\t') {
      os << ch;
    } else if (c == '\r') {
    } else if (c == '\n') {
      os << "\\n";
    } else {
      const unsigned o0 = c & 7, o1 = (c >> 3) & 7, o2 = (c >> 3) & 7;
      os << '\\';
      if (o2) os << o2;
      if (o1) os << o1;
      os << o0;
    }
  }
  os << '"';
}

// Struct members, with anonymous members' own members flattened in.
const char* print_members(std::ostream& os, const TraceValue& v, const char* sep) {
  for (size_t i = 0; i < v.elements.size(); ++i) {
    const std::string& name = i < v.member_names.size() ? v.member_names[i] : std::string();
    if (name.empty()) {
      if (v.elements[i].kind == TraceValue::Kind::structure)
        sep = print_members(os, v.elements[i], sep);
      continue;
    }
    os << sep << name << " = " << v.elements[i];
    sep = ", ";
  }
  return sep;
}

}  // namespace

std::ostream& operator<<(std::ostream& os, const TraceValue& v) {
  using K = TraceValue::Kind;
  switch (v.kind) {
    case K::null:
      return os << "NULL";
    case K::boolean:
      return os << (v.sint ? "true" : "false");
    case K::sint:
      return os << v.sint;
    case K::uint:
      return os << v.uint;
    case K::float32:
    case K::float64: {
      // Shortest decimal that apitrace prints: digits10 + 1 significant digits.
      const auto old =
          os.precision(v.kind == K::float32 ? std::numeric_limits<float>::digits10 + 1
                                            : std::numeric_limits<double>::digits10 + 1);
      if (v.kind == K::float32) {
        os << static_cast<float>(v.real);
      } else {
        os << v.real;
      }
      os.precision(old);
      return os;
    }
    case K::string:
      print_string(os, v.bytes);
      return os;
    case K::blob:
      return os << "blob(" << v.bytes.size() << ")";
    case K::enumeration:
      if (!v.name.empty()) return os << v.name;
      return os << v.sint;
    case K::bitmask:
      return os << v.name;
    case K::array:
      if (v.elements.size() == 1) return os << '&' << v.elements[0];
      os << '{';
      for (size_t i = 0; i < v.elements.size(); ++i) os << (i ? ", " : "") << v.elements[i];
      return os << '}';
    case K::structure:
      os << '{';
      print_members(os, v, "");
      return os << '}';
    case K::pointer:
      return os << "0x" << std::hex << v.uint << std::dec;
    case K::repr:
      return os << v.elements.at(1);
  }
  return os;
}

std::ostream& operator<<(std::ostream& os, const TraceCall& call) {
  os << call.number << ' ' << call.function << '(';
  for (size_t i = 0; i < call.args.size(); ++i) {
    if (i) os << ", ";
    os << (i < call.arg_names.size() ? call.arg_names[i] : std::string()) << " = ";
    if (i < call.arg_recorded.size() && call.arg_recorded[i]) {
      os << call.args[i];
    } else {
      os << '?';
    }
  }
  os << ')';
  if (call.has_ret) os << " = " << call.ret;
  if (call.fake || call.incomplete) {
    os << " //";
    if (call.fake) os << " fake";
    if (call.incomplete) os << " incomplete";
  }
  return os;
}

bool ends_frame(const TraceCall& call) {
  // apitrace's lib/trace/trace_parser_flags.cpp: the calls flagged END_FRAME.
  static const std::unordered_set<std::string> swaps = {
      "glXSwapBuffers",
      "glXSwapBuffersMscOML",
      "eglSwapBuffers",
      "eglSwapBuffersWithDamageEXT",
      "eglSwapBuffersWithDamageKHR",
      "wglSwapBuffers",
      "wglSwapLayerBuffers",
      "wglSwapMultipleBuffers",
      "CGLFlushDrawable",
      "glFrameTerminatorGREMEDY",
      "IDirect3DDevice8::Present",
      "IDirect3DDevice9::Present",
      "IDirect3DDevice9::GetRenderTargetData",
      "IDirect3DDevice9Ex::Present",
      "IDirect3DDevice9Ex::PresentEx",
      "IDirect3DDevice9Ex::GetRenderTargetData",
      "IDirect3DSwapChain9::Present",
      "IDirect3DSwapChain9Ex::Present",
  };
  if (swaps.count(call.function)) return true;
  // ^IDXGI(Decode)?SwapChain\w*::Present\w*$
  const std::string& f = call.function;
  const size_t colon = f.find("::Present");
  if (colon == std::string::npos) return false;
  const std::string cls = f.substr(0, colon);
  return cls.rfind("IDXGISwapChain", 0) == 0 || cls.rfind("IDXGIDecodeSwapChain", 0) == 0;
}

}  // namespace gpusim::gl
