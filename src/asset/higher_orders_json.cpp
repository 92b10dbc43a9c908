#include "higher_orders_json.h"

#include <string>
#include <vector>

#include "deepsea/core/error.h"
#include "json_fields.h"

namespace deepsea {

using json_fields::fail;
using json_fields::get;
using json_fields::integer;
using json_fields::num;
using nlohmann::json;

namespace {

const std::string kWhere = "multiple_scattering";

/// Absent (assets from before the key) or not a boolean: false, as the other flags read.
bool flag(const json& j, const char* key) {
    return j.contains(key) && j[key].is_boolean() && j[key].get<bool>();
}

HigherOrderCheck parse_check(const json& c) {
    const std::string where = kWhere + ".check";
    const json& at = get(c, "max_pixel", where);
    if (!at.is_array() || at.size() != 2 || !at[0].is_number() || !at[1].is_number())
        fail(where + ".max_pixel", "not two numbers");
    HigherOrderCheck k{true,
                       num(c, "mean_rel", where),
                       num(c, "max_rel", where),
                       at[0].get<double>(),
                       at[1].get<double>(),
                       integer(c, "columns", where),
                       integer(c, "paths", where),
                       num(c, "rel_std_error", where)};
    if (!(k.mean_rel >= 0.0 && k.max_rel >= k.mean_rel && k.columns >= 0 && k.paths >= 1 &&
          k.rel_std_error >= 0.0))
        fail(where, "errors must be >= 0 (max >= mean), paths >= 1");
    return k;
}

}  // namespace

json higher_orders_json(const HigherOrderSettings& h) {
    json m = {{"method", "monte carlo, orders >= 2"},
              {"paths", h.paths},
              {"stride", h.stride},
              {"stride_auto", h.stride_auto},
              {"seed", h.seed},
              {"rel_std_error", h.rel_std_error},
              {"fraction", h.fraction},
              {"lamp_samples", h.lamp_samples},
              {"lamp_rel_std_error", h.lamp_rel_std_error}};
    if (h.spacing_rad > 0.0) m["spacing_rad"] = h.spacing_rad;
    if (h.wall) m["wall"] = "absorbing";
    if (h.tail_above > 0.0) {
        m["tail"] = {{"above", h.tail_above}, {"radius", h.tail_radius}};
        if (h.tail_of_mean > 0.0) m["tail"]["of_mean"] = h.tail_of_mean;
    }
    if (h.log_between) m["between_columns"] = "log-bilinear";
    if (h.lamp_symmetric) m["lamp_symmetry"] = "mirror";
    if (h.roulette_after_next_event) m["roulette"] = "after next event";
    const HigherOrderCheck& c = h.check;
    if (c.done) {
        m["check"] = {
            {"mean_rel", c.mean_rel}, {"max_rel", c.max_rel}, {"max_pixel", {c.max_u, c.max_v}},
            {"columns", c.columns},   {"paths", c.paths},     {"rel_std_error", c.rel_std_error}};
    }
    return m;
}

HigherOrderSettings parse_higher_orders(const json& m) {
    HigherOrderSettings h;
    h.paths = integer(m, "paths", kWhere);
    h.stride = integer(m, "stride", kWhere);
    h.stride_auto = flag(m, "stride_auto");
    if (m.contains("wall")) {
        if (m["wall"] != "absorbing") fail(kWhere + ".wall", "not \"absorbing\"");
        h.wall = true;
    }
    const json& seed = get(m, "seed", kWhere);
    if (!seed.is_number_unsigned()) fail(kWhere + ".seed", "not an unsigned integer");
    h.seed = seed.get<std::uint64_t>();
    h.rel_std_error = num(m, "rel_std_error", kWhere);
    h.fraction = num(m, "fraction", kWhere);
    h.lamp_samples = integer(m, "lamp_samples", kWhere);
    h.lamp_rel_std_error = num(m, "lamp_rel_std_error", kWhere);
    if (h.paths < 1 || h.stride < 1 || h.lamp_samples < 1) {
        fail(kWhere, "paths, stride and lamp_samples must be >= 1");
    }
    // Absent before the angular rule and its check: spacing 0 (64 px / step), not checked.
    if (m.contains("spacing_rad")) {
        h.spacing_rad = num(m, "spacing_rad", kWhere);
        if (!(h.spacing_rad > 0.0)) fail(kWhere + ".spacing_rad", "must be > 0");
    }
    // Absent before tail pooling: each column its own paths' light.
    if (m.contains("tail")) {
        const json& t = m["tail"];
        h.tail_above = num(t, "above", kWhere + ".tail");
        h.tail_radius = integer(t, "radius", kWhere + ".tail");
        if (!(h.tail_above > 0.0) || h.tail_radius < 0)
            fail(kWhere + ".tail", "above must be > 0 and radius >= 0");
        // Absent before the threshold followed the column's own orders >= 2.
        if (t.contains("of_mean")) {
            h.tail_of_mean = num(t, "of_mean", kWhere + ".tail");
            if (!(h.tail_of_mean > 0.0)) fail(kWhere + ".tail.of_mean", "must be > 0");
        }
    }
    // Absent before log-bilinear interpolation between columns: bilinear.
    if (m.contains("between_columns")) {
        if (m["between_columns"] != "log-bilinear")
            fail(kWhere + ".between_columns", "not \"log-bilinear\"");
        h.log_between = true;
    }
    // Absent before the lamp tables' odd coefficients were set to 0: as estimated.
    if (m.contains("lamp_symmetry")) {
        if (m["lamp_symmetry"] != "mirror") fail(kWhere + ".lamp_symmetry", "not \"mirror\"");
        h.lamp_symmetric = true;
    }
    // Absent before the roulette came after each segment's next event: before it.
    if (m.contains("roulette")) {
        if (m["roulette"] != "after next event")
            fail(kWhere + ".roulette", "not \"after next event\"");
        h.roulette_after_next_event = true;
    }
    if (m.contains("check")) h.check = parse_check(m["check"]);
    return h;
}

}  // namespace deepsea
