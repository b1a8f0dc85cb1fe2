// A name people read (who acknowledged a request, a token's name): valid
// UTF-8 as given (the JSON and TOML readers check it), counted in
// characters, with no control character that could break a line of a log,
// a page or a PLC's string.
#pragma once

#include <cstddef>
#include <string>

namespace thermocomp {

// Empty when `name` has 1 to `max_characters` characters and no C0 or C1
// control nor DEL; otherwise what is wrong with it, in words.
std::string DisplayNameProblem(const std::string& name, size_t max_characters);

}  // namespace thermocomp
