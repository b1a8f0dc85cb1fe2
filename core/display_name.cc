#include "core/display_name.h"

namespace thermocomp {

namespace {

// Whether the UTF-8 sequence at `p` (of `left` bytes) is a character that
// shows nothing or turns the text's direction: zero-width spaces and
// joiners, the directional marks, embeddings, overrides and isolates, the
// line and paragraph separators, invisible operators, the soft hyphen,
// fillers, variation selectors, tags and the byte-order mark. A name
// holding one reads as another name on a page.
bool Invisible(const unsigned char* p, size_t left) {
  auto in = [&](size_t n, unsigned char a, unsigned char b, unsigned char lo, unsigned char hi) {
    return left >= n && p[0] == a && p[1] == b && p[n - 1] >= lo && p[n - 1] <= hi;
  };
  return in(2, 0xC2, 0xAD, 0xAD, 0xAD) ||                                   // U+00AD
         in(2, 0xCD, 0x8F, 0x8F, 0x8F) ||                                   // U+034F
         in(2, 0xD8, 0x9C, 0x9C, 0x9C) ||                                   // U+061C
         in(3, 0xE1, 0x85, 0x9F, 0xA0) ||                                   // U+115F, U+1160
         in(3, 0xE1, 0xA0, 0x8E, 0x8E) ||                                   // U+180E
         in(3, 0xE2, 0x80, 0x8B, 0x8F) || in(3, 0xE2, 0x80, 0xA8, 0xAE) ||  // U+200B.., U+2028..
         in(3, 0xE2, 0x81, 0xA0, 0xAF) ||                                   // U+2060..U+206F
         in(3, 0xE3, 0x85, 0xA4, 0xA4) ||                                   // U+3164
         in(3, 0xEF, 0xB8, 0x80, 0x8F) ||                                   // U+FE00..U+FE0F
         in(3, 0xEF, 0xBB, 0xBF, 0xBF) ||                                   // U+FEFF
         in(3, 0xEF, 0xBE, 0xA0, 0xA0) ||                                   // U+FFA0
         (left >= 4 && p[0] == 0xF3 && p[1] == 0xA0 && (p[2] == 0x80 || p[2] == 0x81));  // tags
}

// Whether the name begins or ends with a space or a no-break space.
bool Padded(const std::string& name) {
  auto no_break_at = [&](size_t i) {
    return i + 1 < name.size() && static_cast<unsigned char>(name[i]) == 0xC2 &&
           static_cast<unsigned char>(name[i + 1]) == 0xA0;
  };
  if (name.empty()) return false;
  return name.front() == ' ' || no_break_at(0) || name.back() == ' ' ||
         (name.size() >= 2 && no_break_at(name.size() - 2));
}

}  // namespace

std::string DisplayNameProblem(const std::string& name, size_t max_characters) {
  if (Padded(name)) return "must not begin or end with a space";
  size_t characters = 0;
  for (size_t i = 0; i < name.size(); ++i) {
    if (Invisible(reinterpret_cast<const unsigned char*>(name.data()) + i, name.size() - i)) {
      return "must not contain invisible or direction-changing characters";
    }
    const auto byte = static_cast<unsigned char>(name[i]);
    // A character is counted at its lead byte (not a continuation byte).
    if ((byte & 0xC0) != 0x80) ++characters;
    // C1 controls are U+0080..U+009F, in UTF-8 0xC2 0x80..0x9F.
    const bool c1 = byte == 0xC2 && i + 1 < name.size() &&
                    static_cast<unsigned char>(name[i + 1]) >= 0x80 &&
                    static_cast<unsigned char>(name[i + 1]) <= 0x9F;
    if (byte < 0x20 || byte == 0x7F || c1) return "must not contain control characters";
  }
  if (characters == 0 || characters > max_characters) {
    return "must be 1 to " + std::to_string(max_characters) + " characters";
  }
  return "";
}

}  // namespace thermocomp
