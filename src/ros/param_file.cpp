#include <cerrno>
#include <cstdint>
#include <cstdlib>
#include <fstream>

#include "ring_curvature/ros/param_loading.hpp"
#include "ring_curvature/ros/param_table.hpp"

namespace ring_curvature
{

namespace
{

std::string trim(const std::string& s)
{
  const auto b = s.find_first_not_of(" \t\r");
  if (b == std::string::npos)
    return "";
  return s.substr(b, s.find_last_not_of(" \t\r") - b + 1);
}

std::string unquote(const std::string& s)
{
  if (s.size() >= 2 && (s.front() == '"' || s.front() == '\'') && s.back() == s.front())
    return s.substr(1, s.size() - 2);
  return s;
}

class StringReader : public ParamVisitor
{
public:
  explicit StringReader(const std::map<std::string, std::string>& values) : values_(values) {}
  bool visit(const char* key, float& v) override
  {
    const std::string* s = find(key);
    if (!s)
      return true;
    char* end = nullptr;
    errno = 0;
    const double d = std::strtod(s->c_str(), &end);
    if (end == s->c_str() || *end != '\0' || errno != 0)
      return fail(key, *s, "a number");
    v = static_cast<float>(d);
    return true;
  }
  bool visit(const char* key, int& v) override
  {
    const std::string* s = find(key);
    if (!s)
      return true;
    char* end = nullptr;
    errno = 0;
    const long l = std::strtol(s->c_str(), &end, 10);
    if (end == s->c_str() || *end != '\0' || errno != 0 || l < INT32_MIN || l > INT32_MAX)
      return fail(key, *s, "an integer");
    v = static_cast<int>(l);
    return true;
  }
  bool visit(const char* key, bool& v) override
  {
    const std::string* s = find(key);
    if (!s)
      return true;
    // YAML 1.1 spellings that rosparam also accepts.
    if (*s == "true" || *s == "True" || *s == "TRUE")
      v = true;
    else if (*s == "false" || *s == "False" || *s == "FALSE")
      v = false;
    else
      return fail(key, *s, "true or false");
    return true;
  }
  bool visit(const char* key, std::string& v) override
  {
    if (const std::string* s = find(key))
      v = *s;
    return true;
  }

private:
  const std::string* find(const char* key) const
  {
    const auto it = values_.find(key);
    return it == values_.end() ? nullptr : &it->second;
  }
  bool fail(const char* key, const std::string& value, const char* what)
  {
    error = std::string("parameter '") + key + "': '" + value + "' is not " + what;
    return false;
  }
  const std::map<std::string, std::string>& values_;
};

}  // namespace

Status applyParamStrings(const std::map<std::string, std::string>& values, Params& p)
{
  for (const auto& kv : values)
    if (!isParamKey(kv.first))
      return Status::error("unknown parameter '" + kv.first + "' (see config/ring_curvature.yaml for the keys)");
  StringReader reader(values);
  Status s = forEachParam(p, reader);
  if (!s)
    return s;
  return p.validate();
}

Status loadParamsFile(const std::string& path, Params& p)
{
  std::ifstream in(path);
  if (!in)
    return Status::error("cannot open parameter file '" + path + "'");
  std::map<std::string, std::string> values;
  std::string line;
  int number = 0;
  while (std::getline(in, line))
  {
    ++number;
    // A '#' starts a comment unless it is inside a quoted value; our values never hold one.
    const auto hash = line.find('#');
    const std::string body = trim(hash == std::string::npos ? line : line.substr(0, hash));
    if (body.empty() || body == "---")
      continue;
    const auto colon = body.find(':');
    if (colon == std::string::npos || line.find_first_not_of(" \t") != 0)
      return Status::error(path + ":" + std::to_string(number) +
                           ": expected a top-level 'key: value' line (the file is flat, like "
                           "config/ring_curvature.yaml)");
    const std::string key = trim(body.substr(0, colon));
    const std::string value = unquote(trim(body.substr(colon + 1)));
    if (value.empty())
      return Status::error(path + ":" + std::to_string(number) + ": key '" + key + "' has no value");
    values[key] = value;
  }
  Status s = applyParamStrings(values, p);
  if (!s)
    return Status::error(path + ": " + s.message);
  return s;
}

}  // namespace ring_curvature
