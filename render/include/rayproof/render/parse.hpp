// rayproof/render/parse.hpp — scene files (JSON) to Scene, with errors a person can act on.
//
// parse_scene never throws and never crashes, whatever the bytes: a syntax error names
// the source, the line and the column; a schema error names the offending key as a path
// (e.g. objects[2].radius) and says what was expected. The schema is documented in
// render/scenes/README.md.
#pragma once

#include <rayproof/render/scene.hpp>

#include <optional>
#include <string>
#include <string_view>

namespace rayproof::render {

struct ParseError {
    enum class Kind { io, syntax, schema };
    Kind kind = Kind::schema;
    std::string source;   // the file name (or whatever name the caller gave)
    int line = 0;         // syntax errors: 1-based line and column of the offending character
    int column = 0;
    std::string key;      // schema errors: the path of the offending key, e.g. "objects[2].radius"
    std::string message;  // what is wrong and what was expected
    // "scene.json:3:7: syntax error: ..." or "scene.json: objects[2].radius: ..."
    std::string to_string() const;
};

struct ParseResult {
    std::optional<Scene> scene;
    ParseError error;  // meaningful when !scene
    explicit operator bool() const { return scene.has_value(); }
};

ParseResult parse_scene(std::string_view text, std::string_view source_name) noexcept;
ParseResult load_scene(const std::string& path) noexcept;

}  // namespace rayproof::render
