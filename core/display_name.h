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
// direction (U+200B..U+200F, U+2028..U+202E, U+2060..U+2064,
// U+2066..U+2069, U+061C, U+FEFF) and no space at either end; otherwise
// what is wrong with it, in words.
std::string DisplayNameProblem(const std::string& name, size_t max_characters);

}  // namespace thermocomp
