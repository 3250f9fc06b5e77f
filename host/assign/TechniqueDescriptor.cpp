#include "host/assign/TechniqueDescriptor.hpp"

#include <charconv>
#include <stdexcept>

#include "host/util/Error.hpp"

namespace ml {
namespace {

bool parseUnsigned(const std::string& s, unsigned& out) {
  if (s.empty()) return false;
  auto [p, ec] = std::from_chars(s.data(), s.data() + s.size(), out);
  return ec == std::errc() && p == s.data() + s.size();
}

bool contains(const std::vector<std::string>& list, const std::string& v) {
  for (const auto& x : list)
    if (x == v) return true;
  return false;
}

std::string joined(const std::vector<std::string>& list) {
  std::string s;
  for (const auto& x : list) s += (s.empty() ? "" : "|") + x;
  return s;
}

const std::vector<std::string> kOn = {"on", "1", "true"}, kOff = {"off", "0", "false"};

}  // namespace

std::string ParamSpec::renderFlag() const {
  std::string flag = "--" + key;
  for (char& c : flag)
    if (c == '_') c = '-';
  return flag;
}

std::string ParamSpec::allowed() const {
  switch (type) {
    case ParamType::Count:
      return std::to_string(min) + ".." + std::to_string(max) + (choices.empty() ? "" : " or " + joined(choices));
    case ParamType::Choice:
      return joined(choices);
    case ParamType::Switch:
      return "on|off";
    case ParamType::Text:
      break;
  }
  return check ? check("") : std::string("any text");
}

std::string ParamSpec::problem(const std::string& value) const {
  unsigned u = 0;
  switch (type) {
    case ParamType::Count:
      if (contains(choices, value) || (parseUnsigned(value, u) && u >= min && u <= max)) return {};
      break;
    case ParamType::Choice:
      if (contains(choices, value)) return {};
      break;
    case ParamType::Switch:
      if (contains(kOn, value) || contains(kOff, value)) return {};
      break;
    case ParamType::Text:
      if (!check) return {};
      if (value.empty()) break;
      if (const std::string why = check(value); !why.empty()) return "expected " + why;
      return {};
  }
  return "expected " + allowed();
}

bool ParamSpec::sameAs(const ParamSpec& o) const {
  return key == o.key && type == o.type && default_value == o.default_value && min == o.min && max == o.max &&
         choices == o.choices && allowed() == o.allowed();
}

void checkParamValue(const ParamSpec& spec, const std::string& value, const std::string& flag) {
  if (const std::string why = spec.problem(value); !why.empty())
    throw UserError(flag + ": " + spec.key + "=" + value + " is not valid (" + why + ")");
}

void ParamValues::set(const std::string& key, const std::string& value) {
  for (auto& [k, v] : values_)
    if (k == key) {
      v = value;
      return;
    }
  values_.emplace_back(key, value);
}

bool ParamValues::has(const std::string& key) const {
  for (const auto& [k, v] : values_)
    if (k == key) return true;
  return false;
}

const std::string& ParamValues::text(const std::string& key) const {
  for (const auto& [k, v] : values_)
    if (k == key) return v;
  throw std::logic_error("technique parameter '" + key + "' was never set (not in the technique's descriptor?)");
}

unsigned ParamValues::count(const std::string& key) const {
  unsigned u = 0;
  return parseUnsigned(text(key), u) ? u : 0;
}

bool ParamValues::on(const std::string& key) const { return contains(kOn, text(key)); }

const ParamSpec* TechniqueDescriptor::param(const std::string& key) const {
  for (const auto& p : params)
    if (p.key == key) return &p;
  return nullptr;
}

ParamValues TechniqueDescriptor::defaults() const {
  ParamValues v;
  for (const auto& p : params) v.set(p.key, p.default_value);
  return v;
}

// ParamSpec is an aggregate: each builder names only the fields of its type.
ParamSpec countParam(std::string key, std::string default_value, unsigned min, unsigned max, std::string help,
                     std::vector<std::string> words) {
  return {.key = std::move(key), .type = ParamType::Count, .default_value = std::move(default_value),
          .help = std::move(help), .min = min, .max = max, .choices = std::move(words)};
}

ParamSpec choiceParam(std::string key, std::string default_value, std::vector<std::string> choices,
                      std::string help) {
  return {.key = std::move(key), .type = ParamType::Choice, .default_value = std::move(default_value),
          .help = std::move(help), .choices = std::move(choices)};
}

ParamSpec switchParam(std::string key, bool default_value, std::string help) {
  return {.key = std::move(key), .type = ParamType::Switch, .default_value = default_value ? "on" : "off",
          .help = std::move(help)};
}

ParamSpec textParam(std::string key, std::string default_value, std::string help,
                    std::function<std::string(const std::string&)> check) {
  return {.key = std::move(key), .type = ParamType::Text, .default_value = std::move(default_value),
          .help = std::move(help), .check = std::move(check)};
}

ParamSpec kernelShapeParam() {
  return choiceParam("kernel_shape", "auto", {"auto", "cpu", "gpu"},
                     "OpenCL kernel shape: auto (by device type), cpu (a work-item per element, private state), "
                     "gpu (work-groups cooperating through local memory)");
}

}  // namespace ml
