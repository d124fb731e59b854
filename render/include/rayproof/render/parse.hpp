// rayproof/render/parse.hpp — scene files (JSON) to Scene, with errors a person can act on.
//
// parse_scene never throws and never crashes, whatever the bytes: a syntax error names
// the source, the line and the column; a schema error names the offending key as a path
// (e.g. objects[2].radius), the line and column of the offending value (of the key for
// an unknown or duplicate key, of the object for a missing key) and says what was
// expected. A number that overflows a double (1e400) and a key given twice in an object
// are schema errors too. The schema is documented in render/scenes/README.md.
#pragma once

#include <rayproof/render/progress.hpp>
#include <rayproof/render/scene.hpp>

#include <optional>
#include <string>
#include <string_view>

namespace rayproof::render {

struct ParseError {
    enum class Kind { io, syntax, schema, memory };
    Kind kind = Kind::schema;
    std::string source;   // the file name (or whatever name the caller gave)
    int line = 0;         // 1-based line and column (in bytes) of the offending character: set for
    int column = 0;       // syntax errors and schema errors; 0 for io errors and "(scene)"
    std::string key;      // schema errors: the path of the offending key, e.g. "objects[2].radius"
    std::string message;  // what is wrong and what was expected
    // "scene.json:3:7: syntax error: ...", "scene.json:7:21: objects[2].radius: ..." (without
    // ":line:column" when line is 0) or, for io and memory errors, "scene.json: is a directory, ..."
    std::string to_string() const;
};

struct ParseResult {
    std::optional<Scene> scene;
    ParseError error;  // meaningful when !scene
    explicit operator bool() const { return scene.has_value(); }
};

// With a Progress, the phases "parsing" (bytes of JSON read) and "checking" (objects
// read into the Scene) report there.
ParseResult parse_scene(std::string_view text, std::string_view source_name, Progress* progress = nullptr) noexcept;
// Reads a regular file of at most 64 MB (100,000 objects take 15 to 20 MB); a directory,
// a fifo (never waited on), a device or a larger file is an io error saying which. A
// text that may need more memory to parse than is available (memory.hpp) is refused
// before it is parsed (Kind::memory). A Progress gets the phase "reading" (bytes)
// before parse_scene's.
ParseResult load_scene(const std::string& path, Progress* progress = nullptr) noexcept;

}  // namespace rayproof::render
