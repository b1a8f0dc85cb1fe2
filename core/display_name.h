// A name people read (who acknowledged a request, a token's name): valid
// UTF-8 as given (the JSON and TOML readers check it), counted in
// characters, with no control character that could break a line of a log,
// a page or a PLC's string.
#pragma once

#include <cstddef>
#include <string>

namespace thermocomp {

// Empty when `name` has 1 to `max_characters` characters, no C0 or C1
// control nor DEL, no character that shows nothing or turns the text's
// direction (U+00AD, U+034F, U+061C, U+115F, U+1160, U+180E,
// U+200B..U+200F, U+2028..U+202E, U+2060..U+206F, U+3164, U+FE00..U+FE0F,
// U+FEFF, U+FFA0, the tags U+E0000..U+E007F) and no space or no-break
// space at either end; otherwise what is wrong with it, in words.
std::string DisplayNameProblem(const std::string& name, size_t max_characters);

}  // namespace thermocomp
