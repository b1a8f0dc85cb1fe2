#include "core/display_name.h"

namespace thermocomp {

namespace {

// Whether the UTF-8 sequence at `p` (of `left` bytes) is a character that
// shows nothing or turns the text's direction: zero-width spaces and
// joiners, the directional marks, embeddings, overrides and isolates, the
// line and paragraph separators, invisible operators and the byte-order
// mark. A name holding one reads as another name on a page.
bool Invisible(const unsigned char* p, size_t left) {
  if (left >= 2 && p[0] == 0xD8 && p[1] == 0x9C) return true;  // U+061C
  if (left < 3) return false;
  if (p[0] == 0xE2 && p[1] == 0x80)
    return (p[2] >= 0x8B && p[2] <= 0x8F) || (p[2] >= 0xA8 && p[2] <= 0xAE);
  if (p[0] == 0xE2 && p[1] == 0x81)
    return (p[2] >= 0xA0 && p[2] <= 0xA4) || (p[2] >= 0xA6 && p[2] <= 0xA9);
  return p[0] == 0xEF && p[1] == 0xBB && p[2] == 0xBF;  // U+FEFF
}

}  // namespace

std::string DisplayNameProblem(const std::string& name, size_t max_characters) {
  if (!name.empty() && (name.front() == ' ' || name.back() == ' ')) {
    return "must not begin or end with a space";
  }
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
