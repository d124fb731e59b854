// Seeded mutations of the example scene files (byte flips, deletions, insertions of JSON
// punctuation and of hostile numbers, truncations) through parse_scene: every input
// gives a scene or an error with a message (syntax errors with a position inside the
// text, schema errors with a key and a position), nothing throws or crashes, and accepted scenes trace
// a few primary rays in every mode. A deterministic companion to fuzz/scene_fuzz.cpp.
#include "render_support.hpp"

#include <algorithm>
#include <cctype>
#include <fstream>
#include <random>
#include <sstream>

namespace rayproof::render::testing {
namespace {

std::string read_file(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

std::string mutate(std::string s, std::mt19937_64& rng) {
    static const char* const inserts[] = {"{", "}", "[", "]", ",", ":", "\"", "-", "1e308", "-0", "0",
                                          "1e-320", "null", "true", "\"x\"", "[0,0,0]", "{}", "\\u0000", "\xff"};
    const int edits = 1 + int(rng() % 4);
    for (int e = 0; e < edits && !s.empty(); ++e) {
        const std::size_t at = rng() % s.size();
        switch (rng() % 5) {
            case 0: s[at] = char(rng() & 0xff); break;
            case 1: s.erase(at, 1 + rng() % 8); break;
            case 2: s.insert(at, inserts[rng() % std::size(inserts)]); break;
            case 3: s.resize(at); break;
            default: {  // replace a number-looking byte run with a hostile number
                std::size_t end = at;
                while (end < s.size() && (std::isdigit(static_cast<unsigned char>(s[end])) || s[end] == '.')) ++end;
                s.replace(at, end - at, inserts[8 + rng() % 4]);
            }
        }
    }
    return s;
}

TEST(ParserMutations, EveryInputGetsASceneOrAClearError) {
    std::mt19937_64 rng(20240611);
    int accepted = 0, rejected = 0;
    for (const char* name : {"default.json", "cube.json", "hostile.json", "notes.json", "polyhedra.json"}) {
        const std::string original = read_file(scene_path(name));
        ASSERT_FALSE(original.empty()) << name;
        for (int i = 0; i < 400; ++i) {
            const std::string text = mutate(original, rng);
            ParseResult r;
            ASSERT_NO_THROW(r = parse_scene(text, "mutant.json"));
            if (!r) {
                ++rejected;
                const ParseError& e = r.error;
                ASSERT_FALSE(e.message.empty()) << text;
                if (e.kind == ParseError::Kind::syntax) {
                    ASSERT_GE(e.line, 1);
                    ASSERT_GE(e.column, 1);
                } else {
                    ASSERT_EQ(e.kind, ParseError::Kind::schema);
                    ASSERT_FALSE(e.key.empty()) << e.to_string();
                    ASSERT_GE(e.line, 1) << e.to_string();  // schema errors have a place in the text too
                    ASSERT_GE(e.column, 1) << e.to_string();
                }
                continue;
            }
            ++accepted;
            Scene s = *r.scene;
            s.settings.width = s.settings.height = 3;
            s.settings.depth = std::min(s.settings.depth, 3);
            for (Mode m : every_mode()) {
                s.settings.mode = m;
                (void)radiance(s, 1.5, 1.5);
            }
        }
    }
    // Both outcomes occur, so neither branch above is dead.
    EXPECT_GT(accepted, 20);
    EXPECT_GT(rejected, 200);
}

}  // namespace
}  // namespace rayproof::render::testing
