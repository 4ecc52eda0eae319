#include <ros/console.h>

#include <string>
#include <vector>

#include "ring_curvature/ros/param_loading.hpp"
#include "ring_curvature/ros/param_table.hpp"

namespace ring_curvature
{

namespace
{

// A key absent from the server keeps its default; a key present with the wrong type is an
// error (pnh.param() would silently fall back to the default, hiding the user's typo).
class ServerReader : public ParamVisitor
{
public:
  explicit ServerReader(const ros::NodeHandle& pnh) : pnh_(pnh) {}
  bool visit(const char* key, float& v) override { return read(key, v, "a number"); }
  bool visit(const char* key, int& v) override { return read(key, v, "an integer"); }
  bool visit(const char* key, bool& v) override { return read(key, v, "true or false"); }
  bool visit(const char* key, std::string& v) override
  {
    if (!pnh_.hasParam(key))
      return true;
    if (pnh_.getParam(key, v))
    {
      unbracket(v);
      return true;
    }
    int k = 0;  // enums written back by dynamic_reconfigure as integers
    if (pnh_.getParam(key, k))
    {
      v = std::to_string(k);
      return true;
    }
    // A YAML list of names (ring_field: [ring, beam]) means the same as "ring,beam".
    std::vector<std::string> names;
    if (pnh_.getParam(key, names))
    {
      v.clear();
      for (const std::string& n : names)
        v += (v.empty() ? "" : ",") + n;
      return true;
    }
    return fail(key, "a name");
  }

private:
  /// rosrun's `_ring_field:=[ring,beam]` arrives as the string "[ring,beam]" (roscpp does not
  /// parse command-line lists): it means the list, as the YAML list does.
  static void unbracket(std::string& v)
  {
    if (v.size() < 2 || v.front() != '[' || v.back() != ']')
      return;
    std::string inner;
    for (const char c : v.substr(1, v.size() - 2))
      if (c != '\'' && c != '"')
        inner += c;
    v = inner;
  }
  template <class T>
  bool read(const char* key, T& v, const char* what)
  {
    if (!pnh_.hasParam(key) || pnh_.getParam(key, v))
      return true;
    return fail(key, what);
  }
  bool fail(const char* key, const char* what)
  {
    error = "parameter '" + pnh_.resolveName(key) + "' has the wrong type: expected " + what;
    return false;
  }
  const ros::NodeHandle& pnh_;
};

}  // namespace

Status loadParams(const ros::NodeHandle& pnh, Params& p)
{
  ServerReader reader(pnh);
  Status s = forEachParam(p, reader);
  if (!s)
    return s;
  return p.validate();
}

}  // namespace ring_curvature
