#include "forward_psf_json.h"

#include <nlohmann/json.hpp>

#include "deepsea/core/error.h"

namespace deepsea {

using nlohmann::json;

namespace {

[[noreturn]] void fail(const std::string& key, const std::string& problem) {
    throw AssetError("deepsea:forward_psf: " + key + ": " + problem);
}

const json& get(const json& j, const char* key) {
    const auto it = j.find(key);
    if (it == j.end()) fail(key, "missing");
    return *it;
}

std::vector<double> numbers(const json& j, const char* key) {
    const json& x = get(j, key);
    if (!x.is_array()) fail(key, "not an array");
    std::vector<double> out;
    for (const json& e : x) {
        if (!e.is_number()) fail(key, "not all numbers");
        out.push_back(e.get<double>());
    }
    return out;
}

std::vector<Rgb> triples(const json& j, const char* key) {
    const json& x = get(j, key);
    if (!x.is_array()) fail(key, "not an array");
    std::vector<Rgb> out;
    for (const json& e : x) {
        if (!e.is_array() || e.size() != 3 || !e[0].is_number() || !e[1].is_number() ||
            !e[2].is_number())
            fail(key, "needs [r, g, b] number triples");
        out.emplace_back(e[0].get<double>(), e[1].get<double>(), e[2].get<double>());
    }
    return out;
}

json triples(const std::vector<Rgb>& v) {
    json a = json::array();
    for (const Rgb& x : v) a.push_back(json::array({x.r, x.g, x.b}));
    return a;
}

}  // namespace

std::string forward_psf_to_json(const ForwardPsfTable& t) {
    const json j = {{"depth", t.depth},
                    {"ring_edge", t.ring_edge},
                    {"share", triples(t.share)},
                    {"direct", triples(t.direct)},
                    {"std_error", triples(t.std_error)},
                    {"paths", t.paths},
                    {"seed", t.seed}};
    return j.dump();
}

ForwardPsfTable forward_psf_from_json(const std::string& text) {
    json j;
    try {
        j = json::parse(text);
    } catch (const std::exception&) {
        fail("(text)", "not JSON");
    }
    if (!j.is_object()) fail("(text)", "not an object");
    ForwardPsfTable t;
    t.depth = numbers(j, "depth");
    t.ring_edge = numbers(j, "ring_edge");
    t.share = triples(j, "share");
    t.direct = triples(j, "direct");
    t.std_error = triples(j, "std_error");
    const json& p = get(j, "paths");
    if (!p.is_number_integer() || p.get<long long>() < 1 || p.get<long long>() > (1ll << 40))
        fail("paths", "needs an integer >= 1");
    t.paths = int(std::min<long long>(p.get<long long>(), 1ll << 30));
    const json& s = get(j, "seed");
    if (!s.is_number_unsigned() && !(s.is_number_integer() && s.get<long long>() >= 0))
        fail("seed", "needs an integer >= 0");
    t.seed = s.get<std::uint64_t>();
    try {
        t.validate("table");
    } catch (const ConfigError& e) {
        throw AssetError(std::string("deepsea:forward_psf: ") + e.what());
    }
    return t;
}

}  // namespace deepsea
