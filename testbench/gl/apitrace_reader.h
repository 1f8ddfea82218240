// Reads apitrace's binary trace files (.trace) call by call, without apitrace:
// the snappy-compressed container, the header, enter/leave events, the
// signatures defined on first use, and every value type. docs/replay.md lists
// the format facts and their source (apitrace's docs/FORMAT.markdown and
// lib/trace/trace_parser.cpp). Calls come out in the order `apitrace dump`
// prints them, numbered the same way, so a test compares the two call by call.
#pragma once

#include <cstdint>
#include <fstream>
#include <iosfwd>
#include <memory>
#include <string>
#include <vector>

namespace gpusim::gl {

struct TraceValue {
  enum class Kind : uint8_t {
    null,
    boolean,
    sint,
    uint,
    float32,
    float64,
    string,
    blob,
    enumeration,
    bitmask,
    array,
    structure,
    pointer,
    repr
  };
  Kind kind = Kind::null;
  int64_t sint = 0;   // boolean (0 or 1), sint, enumeration's value
  uint64_t uint = 0;  // uint, bitmask, pointer (an opaque address)
  double real = 0.0;  // float32, float64
  std::string bytes;  // string, blob
  // array elements, structure members, repr: [machine value, human value]
  std::vector<TraceValue> elements;
  // Names from the signatures, for printing and for the driver's messages:
  // enumeration: the first symbol whose value matches ("GL_TRIANGLES", empty
  // when none does); bitmask: its flags as `apitrace dump` prints them
  // ("GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT"); structure: the struct's
  // name. A wide string (Windows traces) is read as a UTF-8 string.
  std::string name;
  // structure: the member names, parallel to elements.
  std::vector<std::string> member_names;

  // The value of a scalar (boolean, sint, uint, float32, float64, enumeration,
  // bitmask) converted; throws InputError for other kinds.
  double to_double() const;
  int64_t to_int() const;
  uint64_t to_uint() const;
  bool operator==(const TraceValue&) const;
  bool operator!=(const TraceValue& other) const { return !(*this == other); }
};
// Prints the value the way `apitrace dump --color=never` does where the two can
// agree (numbers, enums, bitmasks, strings, arrays, structures, pointers).
std::ostream& operator<<(std::ostream&, const TraceValue&);

struct TraceCall {
  uint32_t number = 0;  // as `apitrace dump` numbers calls
  uint32_t thread = 0;
  std::string function;                // "glVertex3f"
  std::vector<std::string> arg_names;  // from the signature, parallel to args
  // in the signature's order; an argument never recorded is null
  std::vector<TraceValue> args;
  TraceValue ret;  // null when the function returns nothing
  // What `apitrace dump` tells apart and a null hides: which arguments and
  // whether a return value were recorded at all (dump prints "?" and no " = ").
  std::vector<bool> arg_recorded;
  bool has_ret = false;
  bool fake = false;        // emitted by the tracer, not the program (dump's "// fake")
  bool incomplete = false;  // its leave event never came (program killed)
  bool operator==(const TraceCall&) const;
};
// "12 glVertex3f(x = 1, y = 2, z = 0)", as `apitrace dump` prints a call.
std::ostream& operator<<(std::ostream&, const TraceCall&);

// Whether the call ends a frame (glXSwapBuffers, eglSwapBuffers, and the other
// swap calls apitrace treats as frame ends).
bool ends_frame(const TraceCall& call);

class ApitraceReader {
 public:
  // Throws InputError (hw/input_error.h) with a one-line message: missing or
  // unreadable file, not an apitrace trace, an unsupported format version,
  // corrupt data.
  explicit ApitraceReader(const std::string& path);
  ~ApitraceReader();
  ApitraceReader(const ApitraceReader&) = delete;
  ApitraceReader& operator=(const ApitraceReader&) = delete;

  // The next call, in the order `apitrace dump` prints them (calls complete at
  // their leave event; a call whose leave never came because the program was
  // killed is still returned, as apitrace does). false at the end of the
  // trace.
  bool next(TraceCall& call);
  uint64_t bytes_read() const;  // of the file, for progress
  uint64_t file_size() const;
  const std::string& path() const;

  uint32_t version() const;           // format version (0..6)
  uint32_t semantic_version() const;  // equals version() before 6
  // The header's properties (version 6), e.g. "process.name".
  const std::vector<std::pair<std::string, std::string>>& properties() const;

 private:
  struct State;
  std::unique_ptr<State> m_state;
};

}  // namespace gpusim::gl
