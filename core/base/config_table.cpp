#include "core/base/config_table.h"

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>

namespace ale {
namespace {

std::string number_text(double v, ConfigType type) {
  char buf[64];
  if (type == ConfigType::kInt) {
    std::snprintf(buf, sizeof buf, "%lld", static_cast<long long>(v));
  } else if (type == ConfigType::kFloat) {
    std::snprintf(buf, sizeof buf, "%.7g", v);  // a float's digits: 0.9f prints as 0.9
  } else {
    std::snprintf(buf, sizeof buf, "%.10g", v);
  }
  return buf;
}

std::string names_of(const char* const* names) {
  std::string list;
  for (const char* const* n = names; *n != nullptr; ++n) list += (list.empty() ? "" : "|") + std::string(*n);
  return list;
}

// The leaf `key` of `table` and the struct within `object` that holds it; nullptr when unknown.
const ConfigField* find(const ConfigTable& table, void* object, const std::string& key, void** owner) {
  for (std::size_t i = 0; i < table.count; ++i) {
    const ConfigField& f = table.fields[i];
    const std::string name = f.key;
    if (f.type == ConfigType::kTable) {
      if (key.size() > name.size() && key.compare(0, name.size(), name) == 0 && key[name.size()] == '.')
        return find(*f.table, f.at(object), key.substr(name.size() + 1), owner);
    } else if (key == name) {
      *owner = object;
      return &f;
    }
  }
  return nullptr;
}

}  // namespace

void for_each_field(const ConfigTable& table, const void* object, const std::string& prefix,
                    const std::function<void(const std::string& key, const ConfigField& field, const void* owner)>& visit) {
  for (std::size_t i = 0; i < table.count; ++i) {
    const ConfigField& f = table.fields[i];
    if (f.type == ConfigType::kTable)
      for_each_field(*f.table, f.at(const_cast<void*>(object)), prefix + f.key + ".", visit);
    else
      visit(prefix + f.key, f, object);
  }
}

std::string format_field(const ConfigField& f, const void* object) {
  void* member = f.at != nullptr ? f.at(const_cast<void*>(object)) : nullptr;  // read only
  switch (f.type) {
    case ConfigType::kInt: return number_text(*static_cast<const int*>(member), f.type);
    case ConfigType::kDouble: return number_text(*static_cast<const double*>(member), f.type);
    case ConfigType::kFloat: return number_text(*static_cast<const float*>(member), f.type);
    case ConfigType::kBool: return *static_cast<const bool*>(member) ? "true" : "false";
    case ConfigType::kString: return *static_cast<const std::string*>(member);
    case ConfigType::kChoice: return f.choices[f.get_choice(object)];
    case ConfigType::kTable: return "";
  }
  return "";
}

std::string default_of(const ConfigTable& table, const std::string& key) {
  void* owner = nullptr;
  const ConfigField* f = find(table, const_cast<void*>(table.defaults), key, &owner);
  return f != nullptr ? format_field(*f, owner) : std::string();
}

std::string range_of(const ConfigField& f) {
  switch (f.type) {
    case ConfigType::kInt:
    case ConfigType::kDouble:
    case ConfigType::kFloat: return number_text(f.min, f.type) + ".." + number_text(f.max, f.type);
    case ConfigType::kBool: return "true|false";
    case ConfigType::kString: return f.choices != nullptr ? names_of(f.choices) : "text";
    case ConfigType::kChoice: return names_of(f.choices);
    case ConfigType::kTable: return "";
  }
  return "";
}

Status set_field(const ConfigTable& table, void* object, const std::string& key, const std::string& v,
                 const std::string& where) {
  void* owner = nullptr;
  const ConfigField* found = find(table, object, key, &owner);
  if (found == nullptr) return not_found(where + ": unknown key '" + key + "'");
  const ConfigField& f = *found;
  const auto out_of_range = [&] {
    return invalid_argument(where + ": " + v + " is out of range [" + number_text(f.min, f.type) + ", " +
                            number_text(f.max, f.type) + "]");
  };
  switch (f.type) {
    case ConfigType::kInt: {
      errno = 0;
      char* end = nullptr;
      const long x = std::strtol(v.c_str(), &end, 10);
      if (v.empty() || *end != '\0' || errno != 0) return invalid_argument(where + ": '" + v + "' is not an integer");
      if (static_cast<double>(x) < f.min || static_cast<double>(x) > f.max) return out_of_range();
      *static_cast<int*>(f.at(owner)) = static_cast<int>(x);
      return {};
    }
    case ConfigType::kDouble:
    case ConfigType::kFloat: {
      errno = 0;
      char* end = nullptr;
      const double x = std::strtod(v.c_str(), &end);
      if (v.empty() || *end != '\0' || errno != 0 || std::isnan(x))
        return invalid_argument(where + ": '" + v + "' is not a number");
      if (x < f.min || x > f.max) return out_of_range();
      if (f.type == ConfigType::kFloat) {
        *static_cast<float*>(f.at(owner)) = static_cast<float>(x);
      } else {
        *static_cast<double*>(f.at(owner)) = x;
      }
      return {};
    }
    case ConfigType::kBool: {
      bool& b = *static_cast<bool*>(f.at(owner));
      if (v == "true" || v == "1" || v == "yes") b = true;
      else if (v == "false" || v == "0" || v == "no") b = false;
      else return invalid_argument(where + ": '" + v + "' is not a boolean (true/false)");
      return {};
    }
    case ConfigType::kString: {
      if (f.choices != nullptr) {
        bool allowed = false;
        for (const char* const* n = f.choices; *n != nullptr; ++n) allowed = allowed || v == *n;
        if (!allowed) return invalid_argument(where + ": '" + v + "' is not one of " + names_of(f.choices));
      }
      *static_cast<std::string*>(f.at(owner)) = v;
      return {};
    }
    case ConfigType::kChoice: {
      for (int i = 0; f.choices[i] != nullptr; ++i)
        if (v == f.choices[i]) {
          f.set_choice(owner, i);
          return {};
        }
      return invalid_argument(where + ": '" + v + "' is not one of " + names_of(f.choices));
    }
    case ConfigType::kTable: break;
  }
  return not_found(where + ": unknown key '" + key + "'");
}

Status check_ranges(const ConfigTable& table, const void* object, const std::string& prefix) {
  Status first;
  for_each_field(table, object, prefix, [&](const std::string& key, const ConfigField& f, const void* owner) {
    if (!first.ok() || (f.type != ConfigType::kInt && f.type != ConfigType::kDouble && f.type != ConfigType::kFloat))
      return;
    const void* member = f.at(const_cast<void*>(owner));
    const double v = f.type == ConfigType::kInt     ? *static_cast<const int*>(member)
                     : f.type == ConfigType::kFloat ? *static_cast<const float*>(member)
                                                    : *static_cast<const double*>(member);
    if (!(v >= f.min && v <= f.max))
      first = invalid_argument(key + ": " + number_text(v, f.type) + " is out of range [" + number_text(f.min, f.type) +
                               ", " + number_text(f.max, f.type) + "]");
  });
  return first;
}

}  // namespace ale
