// "Did you mean": the candidate nearest to a misspelt word, by edit distance
// (insertions, deletions and substitutions, each 1), if it is close enough
// to be what was meant: at most a third of the word's length, and at least
// 1. Shared by the options, the deck's keywords and the host's component
// types and parameters.
#pragma once

#include <string>
#include <vector>

namespace config {

size_t edit_distance(const std::string& a, const std::string& b);
// "" when no candidate is close enough.
std::string nearest(const std::string& word, const std::vector<std::string>& candidates);

}  // namespace config
