#pragma once
// Internal: reading the `deepsea:bake` JSON's fields with one-line errors naming the key
// (asset_json.cpp, port_json.cpp, higher_orders_json.cpp share them).

#include <nlohmann/json.hpp>
#include <string>

#include "deepsea/core/error.h"

namespace deepsea::json_fields {

using nlohmann::json;

[[noreturn]] inline void fail(const std::string& key, const std::string& problem) {
    throw AssetError("deepsea:bake: " + key + ": " + problem);
}

/// `where`.`key` of object j.
inline const json& get(const json& j, const char* key, const std::string& where) {
    if (!j.is_object()) fail(where, "not an object");
    const auto it = j.find(key);
    if (it == j.end()) fail(where + "." + key, "missing");
    return *it;
}

inline double num(const json& j, const char* key, const std::string& where) {
    const json& x = get(j, key, where);
    if (!x.is_number()) fail(where + "." + key, "not a number");
    return x.get<double>();
}

inline int integer(const json& j, const char* key, const std::string& where) {
    const json& x = get(j, key, where);
    if (!x.is_number_integer()) fail(where + "." + key, "not an integer");
    return x.get<int>();
}

}  // namespace deepsea::json_fields
