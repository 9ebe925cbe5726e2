// The paper's molecules (tests/data/paper), read once per benchmark program.
#pragma once

#include <map>
#include <string>

#include "build/io/molecule.hpp"

namespace surftrace::bench {

inline const build::Molecule& paperMolecule(const std::string& name) {
  static std::map<std::string, build::Molecule> cache;
  auto it = cache.find(name);
  if (it == cache.end())
    it = cache.emplace(name, build::readMolecule(std::string(SURFTRACE_TEST_DATA) + "/paper/" + name)).first;
  return it->second;
}

}  // namespace surftrace::bench
