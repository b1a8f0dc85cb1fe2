#include "core/display_name.h"

namespace thermocomp {

std::string DisplayNameProblem(const std::string& name, size_t max_characters) {
  size_t characters = 0;
  for (size_t i = 0; i < name.size(); ++i) {
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
