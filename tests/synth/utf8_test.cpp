// UTF-8 checks for outside text (issue 39: a program's or a scene's bytes that are not
// UTF-8 ended the whole run with exit 3 when a JSON file was written).
#include "synth/utf8.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

namespace grapebench {
namespace {

constexpr auto npos = std::string_view::npos;

TEST(Utf8, ValidTextPassesAndTheFirstBadByteIsNamed) {
  for (const char* good : {"", "plain", "\xC3\xA9t\xC3\xA9", "\xE2\x82\xAC", "\xF0\x9F\x8D\x87", "\xF4\x8F\xBF\xBF",
                           "\xED\x9F\xBF", "\xEE\x80\x80"})
    EXPECT_EQ(invalid_utf8_at(good), npos) << good;
  const std::pair<std::string, std::size_t> bad[] = {
      {"caf\xE9 noir", 3},           // Latin-1
      {"\xFF\xFE" "a\0", 0},         // a UTF-16 byte-order mark
      {"ab\xC0\xAF", 2},             // overlong '/'
      {"\xE0\x80\xAF", 0},           // overlong, three bytes
      {"x\xED\xA0\x80", 1},          // a surrogate
      {"\xF4\x90\x80\x80", 0},       // past U+10FFFF
      {"ok\xE2\x82", 2},             // cut short
      {"\x80", 0},                   // a lone continuation byte
      {"\xF5\x80\x80\x80", 0}};
  for (const auto& [text, at] : bad) EXPECT_EQ(invalid_utf8_at(text), at) << text;
}

TEST(Utf8, EscapedTextIsUtf8AndKeepsTheGoodCharacters) {
  const std::string s = escape_invalid_utf8("caf\xE9 \xC3\xA9 \xFF");
  EXPECT_EQ(s, "caf\\xE9 \xC3\xA9 \\xFF");
  EXPECT_EQ(invalid_utf8_at(s), npos);
  EXPECT_NO_THROW((void)nlohmann::json(s).dump());
}

}  // namespace
}  // namespace grapebench
