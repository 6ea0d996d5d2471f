// Configuration written once: one table per configuration struct, each row a member's key (its
// path in the struct), type, range and help. The app's parser and --print-config, the reference in
// docs/configuration.md (a test compares it) and the core's validate() all read the same rows;
// defaults are the struct's own (read from a default-constructed one).
//
//   constexpr ConfigField kRows[] = {number<&Params::alpha>("alpha", 1e-3, 1, "why it matters")};
//   constexpr ConfigTable kTable = table_of<Params>(kRows);
#pragma once

#include <cstddef>
#include <functional>
#include <string>
#include <type_traits>

#include "core/base/status.h"

namespace ale {

enum class ConfigType { kInt, kDouble, kFloat, kBool, kString, kChoice, kTable };

struct ConfigTable;

struct ConfigField {
  const char* key = "";  // the member's path relative to the table's struct
  ConfigType type = ConfigType::kInt;
  double min = 0.0;  // kInt, kDouble, kFloat: the inclusive range
  double max = 0.0;
  const char* help = "";
  void* (*at)(void* object) = nullptr;       // the member (int, double, bool, std::string, nested struct)
  const char* const* choices = nullptr;      // kChoice: names by enum value; kString: allowed values (or none); nullptr-ended
  int (*get_choice)(const void* object) = nullptr;
  void (*set_choice)(void* object, int value) = nullptr;
  const ConfigTable* table = nullptr;        // kTable: the nested struct's table
};

struct ConfigTable {
  const ConfigField* fields = nullptr;
  std::size_t count = 0;
  const void* defaults = nullptr;  // a default-constructed struct
};

namespace config_detail {
template <class>
struct Member;
template <class S, class T>
struct Member<T S::*> {
  using Object = S;
  using Type = T;
};
template <auto M>
void* at(void* object) {
  return &(static_cast<typename Member<decltype(M)>::Object*>(object)->*M);
}
template <auto M>
int get_choice(const void* object) {
  return static_cast<int>(static_cast<const typename Member<decltype(M)>::Object*>(object)->*M);
}
template <auto M>
void set_choice(void* object, int value) {
  static_cast<typename Member<decltype(M)>::Object*>(object)->*M = static_cast<typename Member<decltype(M)>::Type>(value);
}
template <class S>
inline const S kDefaults{};
}  // namespace config_detail

// An int, double or float member within [min, max].
template <auto M>
constexpr ConfigField number(const char* key, double min, double max, const char* help) {
  using T = typename config_detail::Member<decltype(M)>::Type;
  static_assert(std::is_same_v<T, int> || std::is_same_v<T, double> || std::is_same_v<T, float>,
                "number<> wants an int, double or float member");
  ConfigField f;
  f.key = key;
  f.type = std::is_same_v<T, int> ? ConfigType::kInt : std::is_same_v<T, float> ? ConfigType::kFloat : ConfigType::kDouble;
  f.min = min;
  f.max = max;
  f.help = help;
  f.at = &config_detail::at<M>;
  return f;
}

template <auto M>
constexpr ConfigField flag(const char* key, const char* help) {
  static_assert(std::is_same_v<typename config_detail::Member<decltype(M)>::Type, bool>, "flag<> wants a bool");
  ConfigField f;
  f.key = key;
  f.type = ConfigType::kBool;
  f.help = help;
  f.at = &config_detail::at<M>;
  return f;
}

// A std::string member; `allowed` (nullptr-ended) restricts its values.
template <auto M>
constexpr ConfigField text(const char* key, const char* help, const char* const* allowed = nullptr) {
  static_assert(std::is_same_v<typename config_detail::Member<decltype(M)>::Type, std::string>, "text<> wants a string");
  ConfigField f;
  f.key = key;
  f.type = ConfigType::kString;
  f.help = help;
  f.at = &config_detail::at<M>;
  f.choices = allowed;
  return f;
}

// An enum member; names[v] is the name of value v (nullptr-ended).
template <auto M>
constexpr ConfigField choice(const char* key, const char* const* names, const char* help) {
  static_assert(std::is_enum_v<typename config_detail::Member<decltype(M)>::Type>, "choice<> wants an enum");
  ConfigField f;
  f.key = key;
  f.type = ConfigType::kChoice;
  f.help = help;
  f.choices = names;
  f.get_choice = &config_detail::get_choice<M>;
  f.set_choice = &config_detail::set_choice<M>;
  return f;
}

// A nested struct with its own table; its keys are "key.<nested key>".
template <auto M>
constexpr ConfigField nested(const char* key, const ConfigTable& table) {
  ConfigField f;
  f.key = key;
  f.type = ConfigType::kTable;
  f.at = &config_detail::at<M>;
  f.table = &table;
  return f;
}

template <class S, std::size_t N>
constexpr ConfigTable table_of(const ConfigField (&fields)[N]) {
  return {fields, N, &config_detail::kDefaults<S>};
}

// Visits every leaf field of `table` in order with its full key (prefix + path) and the struct
// (within `object`) that holds it.
void for_each_field(const ConfigTable& table, const void* object, const std::string& prefix,
                    const std::function<void(const std::string& key, const ConfigField& field, const void* owner)>& visit);

// The value of `field` in `object` as a config file writes it ("1.5", "true", "ale", "/dev/video0").
std::string format_field(const ConfigField& field, const void* object);
// The default of the leaf `key` of `table`, formatted; "" for an unknown key.
std::string default_of(const ConfigTable& table, const std::string& key);
// The allowed values of `field` as text: "1..10000", "0.001..1", "true|false", "ale|baseline|clahe",
// "any text".
std::string range_of(const ConfigField& field);

// Sets the leaf `key` of `table` in `object` from `value`. kNotFound for an unknown key;
// kInvalidArgument "<where>: '<value>' is not ..." or "<where>: <value> is out of range [...]".
Status set_field(const ConfigTable& table, void* object, const std::string& key, const std::string& value,
                 const std::string& where);
// The first numeric member of `object` outside its range: kInvalidArgument
// "<prefix><key>: <value> is out of range [min, max]".
Status check_ranges(const ConfigTable& table, const void* object, const std::string& prefix = "");

}  // namespace ale
