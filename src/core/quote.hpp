#pragma once
// User text echoed in a message (issue 26 item 17): a name or a formula from a
// case may be a megabyte long or hold terminal control sequences (ESC, BEL). An
// error stays one readable line: control characters are escaped (\n, \t, \x1b),
// C1 controls too (U+0080–U+009F, which some terminals obey), and long text is cut
// with the count of its characters.
#include <fmt/format.h>

#include <cstddef>
#include <string>
#include <string_view>
#include <utility>

namespace vpc {

/// The length at which echoed text is cut, by default.
inline constexpr std::size_t kEchoLength = 100;

/// The printable form of `s` cut after about `max` bytes (at a character boundary),
/// and whether it was cut.
inline std::pair<std::string, bool> printable_part(std::string_view s, std::size_t max) {
  std::string out;
  std::size_t i = 0;
  for (; i < s.size() && out.size() < max; ++i) {
    const auto c = static_cast<unsigned char>(s[i]);
    const auto next = i + 1 < s.size() ? static_cast<unsigned char>(s[i + 1]) : 0;
    if (c == '\n') out += "\\n";
    else if (c == '\t') out += "\\t";
    else if (c < 0x20 || c == 0x7f) out += fmt::format("\\x{:02x}", c);
    else if (c == 0xc2 && next >= 0x80 && next <= 0x9f) out += fmt::format("\\u{:04x}", s[++i] & 0xff);
    else out += static_cast<char>(c);
  }
  while (i < s.size() && (static_cast<unsigned char>(s[i]) & 0xc0) == 0x80) out += s[i++];  // the character under way
  return {out, i < s.size()};
}

/// The number of UTF-8 characters of `s` (its bytes that do not continue a character).
inline std::size_t character_count(std::string_view s) {
  std::size_t n = 0;
  for (char c : s) n += (static_cast<unsigned char>(c) & 0xc0) != 0x80;
  return n;
}

/// `s` made printable and cut: "abc… (300000 characters)".
inline std::string printable(std::string_view s, std::size_t max = kEchoLength) {
  auto [p, cut] = printable_part(s, max);
  return cut ? fmt::format("{}… ({} characters)", p, character_count(s)) : p;
}

/// `s` in single quotes, made printable and cut: 'abc', or 'abc…' (300000 characters).
/// (Not "quoted": std::quoted would be found too, by argument-dependent lookup.)
inline std::string quote(std::string_view s, std::size_t max = kEchoLength, char mark = '\'') {
  auto [p, cut] = printable_part(s, max);
  return cut ? fmt::format("{}{}…{} ({} characters)", mark, p, mark, character_count(s)) : mark + p + mark;
}

/// A formula, in double quotes as a case file writes it: "2*w".
inline std::string quote_formula(std::string_view s) { return quote(s, kEchoLength, '"'); }

}  // namespace vpc
