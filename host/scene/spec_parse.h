// Strict parsing of the command-line forms of cameras, lights and sizes: every character must belong to
// a number, numbers must be finite, and errors name the part that is wrong.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include <glm/glm.hpp>

namespace penumbra::detail {

// Splits on `sep`, keeping empty parts ("a::b" -> "a", "", "b").
std::vector<std::string_view> splitParts(std::string_view text, char sep);
// The whole of `text` as one finite number; throws std::invalid_argument("WHAT: expected ...").
float parseFiniteFloat(std::string_view text, std::string_view what);
// The whole of `text` as one integer.
long long parseInteger(std::string_view text, std::string_view what);
// "X,Y,Z", each finite.
glm::vec3 parseVec3(std::string_view text, std::string_view what);
// The shortest decimal form that parses back to the same float.
std::string formatFloat(float value);
std::string formatVec3(const glm::vec3& v);

}  // namespace penumbra::detail
