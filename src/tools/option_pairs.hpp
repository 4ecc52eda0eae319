// Command lines of "--name value" pairs, as the lab's simpler tools take them.
#pragma once

#include <functional>
#include <initializer_list>
#include <iostream>
#include <string>
#include <utility>

namespace ring_curvature
{
namespace bench
{

/// An option's name and what to do with its value.
using OptionPair = std::pair<const char*, std::function<void(const std::string&)>>;

/// Stores the value into `target`: for an option that is a plain string.
inline std::function<void(const std::string&)> into(std::string& target)
{
  return [&target](const std::string& v) { target = v; };
}

/// Hands argv[1..] to `options` pair by pair. A lone last argument is left unread (the caller
/// decides what it means). False, after "TOOL: unknown argument 'NAME'" on stderr, at a name
/// that is not among `options`.
inline bool readOptionPairs(int argc, char** argv, const char* tool, std::initializer_list<OptionPair> options)
{
  for (int i = 1; i + 1 < argc; i += 2)
  {
    const std::string a = argv[i];
    bool known = false;
    for (const OptionPair& o : options)
      if (a == o.first)
      {
        o.second(argv[i + 1]);
        known = true;
        break;
      }
    if (!known)
    {
      std::cerr << tool << ": unknown argument '" << a << "'\n";
      return false;
    }
  }
  return true;
}

}  // namespace bench
}  // namespace ring_curvature
