// Damaging a capture's blobs in ways that only their content hashes can tell.
#pragma once

#include <filesystem>
#include <set>
#include <string>

namespace nightcap::test {

// Every blob the manifest of `folder` names gets other content: a resource's blob decodes to other
// bytes of the same size, a shader's keeps its size (SPIR-V: a whole number of words) and loses
// its content. An empty resource has no other content and is left as it is. Returns the blobs
// damaged, as the manifest names them; fails the test if blobs/ holds a file the manifest does
// not name.
std::set<std::string> damage_every_blob(const std::filesystem::path& folder);

}  // namespace nightcap::test
