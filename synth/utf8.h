// Outside text (scene files, programs' output and answers) checked as UTF-8, and
// quoted in messages that must stay UTF-8 themselves (JSON case files refuse
// anything else).
#pragma once

#include <cstddef>
#include <string>
#include <string_view>

namespace grapebench {

// The byte offset where `text` stops being UTF-8 (RFC 3629: no overlong forms, no
// surrogates, nothing past U+10FFFF), or std::string_view::npos when it is UTF-8.
std::size_t invalid_utf8_at(std::string_view text);
// `text` with every byte outside valid UTF-8 written as \xNN: for messages that quote
// outside text (a program's stderr, a file's bytes) and must stay UTF-8 themselves.
std::string escape_invalid_utf8(std::string_view text);

}  // namespace grapebench
