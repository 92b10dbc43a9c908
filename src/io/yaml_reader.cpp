#include "yaml_reader.h"

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <utility>

#include "deepsea/core/error.h"
#include "deepsea/core/input_file.h"
#include "deepsea/optics/schema.h"

namespace deepsea::yaml {

namespace {

/// What a node holds, for "expected X, got Y" messages.
std::string describe(const YAML::Node& n) {
    switch (n.Type()) {
        case YAML::NodeType::Null:
            return "nothing";
        case YAML::NodeType::Scalar:
            return (n.Tag() == "!" ? "the string \"" : "'") + n.Scalar() +
                   (n.Tag() == "!" ? "\"" : "'");
        case YAML::NodeType::Sequence:
            return "a list";
        case YAML::NodeType::Map:
            return "a map";
        default:
            return "an undefined value";
    }
}

std::string read_text(const std::string& path) { return read_text_file(path, "a YAML file"); }

}  // namespace

int line_of(const YAML::Mark& m) { return m.is_null() ? 1 : m.line + 1; }

std::string child_path(const std::string& parent, const std::string& key) {
    return parent.empty() ? key : parent + "." + key;
}

std::string join(const std::vector<std::string>& v, const char* sep) {
    std::string out;
    for (const auto& s : v) out += (out.empty() ? "" : sep) + s;
    return out;
}

std::string fmt(double v) {
    char buf[64];
    const auto r = std::to_chars(buf, buf + sizeof buf, v);
    return std::string(buf, r.ptr);
}

// ---------------------------------------------------------------------------------------------
// Document

Document::Document(const std::string& text, std::string file) : m_file(std::move(file)) {
    YAML::Node root;
    try {
        root = YAML::Load(text);
    } catch (const YAML::Exception& e) {
        throw ConfigError(m_file + ":" + std::to_string(line_of(e.mark)) +
                          ": YAML syntax error: " + one_line(e.msg));
    }
    m_root = Field{root, root.Mark(), "", root.Mark()};
}

Document Document::load(const std::string& path) { return Document(read_text(path), path); }

void Document::fail(const YAML::Mark& mark, const std::string& path,
                    const std::string& problem) const {
    throw ConfigError(m_file + ":" + std::to_string(line_of(mark)) + ": " +
                      (path.empty() ? std::string("(top level)") : path) + ": " + problem);
}

void Document::fail(const SchemaError& e) const {
    // "rig.lights[1].rid.table.value[1]" -> ...value -> ...table -> ... until one was read.
    std::string p = e.key();
    while (!p.empty() && !m_marks.count(p)) {
        const auto cut = p.find_last_of(".[");
        p = cut == std::string::npos ? std::string() : p.substr(0, cut);
    }
    fail(p.empty() ? m_root.mark : m_marks.at(p), e.key(), e.problem());
}

Field Document::field(const YAML::Node& value, const YAML::Mark& key, std::string path) const {
    const YAML::Mark m = value.Mark();
    // A null value ("key:" with nothing after it) may carry no mark of its own.
    Field f{value, m.is_null() ? key : m, std::move(path), key};
    m_marks[f.path] = f.mark;
    return f;
}

double Document::number(const Field& f) const {
    // A quoted scalar ("1.0") is a string in YAML: strict files do not coerce it.
    if (!f.node.IsScalar() || f.node.Tag() == "!")
        fail(f, "expected a number, got " + describe(f.node));
    double v = 0.0;
    try {
        v = f.node.as<double>();
    } catch (const YAML::Exception&) {
        fail(f, "expected a number, got " + describe(f.node));
    }
    if (!std::isfinite(v)) fail(f, "must be a finite number");
    return v;
}

int Document::integer(const Field& f) const {
    if (!f.node.IsScalar() || f.node.Tag() == "!")
        fail(f, "expected an integer, got " + describe(f.node));
    long long v = 0;
    try {
        v = f.node.as<long long>();
    } catch (const YAML::Exception&) {
        fail(f, "expected an integer, got " + describe(f.node));
    }
    if (v < std::numeric_limits<int>::min() || v > std::numeric_limits<int>::max())
        fail(f, "integer out of range");
    return int(v);
}

bool Document::boolean(const Field& f) const {
    if (!f.node.IsScalar() || f.node.Tag() == "!")
        fail(f, "expected true or false, got " + describe(f.node));
    try {
        return f.node.as<bool>();
    } catch (const YAML::Exception&) {
        fail(f, "expected true or false, got " + describe(f.node));
    }
}

std::string Document::string(const Field& f) const {
    if (!f.node.IsScalar()) fail(f, "expected a string, got " + describe(f.node));
    return f.node.Scalar();
}

std::vector<Field> Document::list(const Field& f) const {
    if (!f.node.IsSequence()) fail(f, "expected a list, got " + describe(f.node));
    std::vector<Field> out;
    for (std::size_t i = 0; i < f.node.size(); ++i)
        out.push_back(field(f.node[i], f.node[i].Mark().is_null() ? f.mark : f.node[i].Mark(),
                            f.path + "[" + std::to_string(i) + "]"));
    return out;
}

std::vector<double> Document::numbers(const Field& f, std::size_t n, const char* what) const {
    const auto items = list(f);
    if (items.size() != n)
        fail(f, "expected a list of " + std::to_string(n) + " numbers" +
                    (*what ? std::string(" [") + what + "]" : std::string()) + ", got " +
                    std::to_string(items.size()));
    std::vector<double> out;
    for (const Field& x : items) out.push_back(number(x));
    return out;
}

Vec3 Document::vec3(const Field& f) const {
    const auto v = numbers(f, 3, "x, y, z");
    return {v[0], v[1], v[2]};
}

Rgb Document::rgb(const Field& f) const {
    const auto v = numbers(f, 3, "r, g, b");
    return {v[0], v[1], v[2]};
}

// ---------------------------------------------------------------------------------------------
// MapView

MapView::MapView(const Document& doc, const Field& f,
                 const std::optional<std::vector<std::string>>& allowed)
    : m_doc(doc), m_field(f), m_allowed(allowed) {
    if (!f.node.IsMap()) doc.fail(f, "expected a map, got " + describe(f.node));
    for (auto it = f.node.begin(); it != f.node.end(); ++it) {
        const YAML::Node k = it->first;  // a copy: it-> yields a temporary
        const std::string path = child_path(f.path, k.IsScalar() ? k.Scalar() : "?");
        if (!k.IsScalar()) doc.fail(k.Mark(), f.path, "keys must be plain names");
        const std::string key = k.Scalar();
        if (allowed && std::find(allowed->begin(), allowed->end(), key) == allowed->end())
            doc.fail(k.Mark(), path, "unknown key (expected " + join(*allowed) + ")");
        if (m_entries.count(key))
            doc.fail(k.Mark(), path,
                     "repeated key (first given on line " +
                         std::to_string(line_of(m_entries.at(key).mark)) + ")");
        m_entries.emplace(key, doc.field(it->second, k.Mark(), path));
        m_order.push_back(key);
    }
}

const Field& MapView::need(const std::string& key) const {
    const Field* f = opt(key);
    if (!f)
        m_doc.fail(m_field.key_mark.is_null() ? m_field.mark : m_field.key_mark,
                   child_path(m_field.path, key), "missing required key");
    return *f;
}

const Field* MapView::opt(const std::string& key) const {
    // A key the schema does not list can never be present: asking for it is a typo here.
    if (m_allowed && std::find(m_allowed->begin(), m_allowed->end(), key) == m_allowed->end())
        throw std::logic_error("MapView: '" + key + "' is not among the allowed keys");
    const auto it = m_entries.find(key);
    return it == m_entries.end() ? nullptr : &it->second;
}

}  // namespace deepsea::yaml
