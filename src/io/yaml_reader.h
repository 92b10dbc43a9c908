#pragma once
/// \file The strict YAML reader under every YAML file deepsea reads (the camera / rig / water
/// configs, the bake-library manifest, DeepSeaRenderer configs): typed getters and maps with
/// an allowed key set, every error a ConfigError "file:line: key.path: problem". Private to
/// io (under src/, not include/): only io sees yaml-cpp.

#include <yaml-cpp/yaml.h>

#include <array>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "deepsea/core/vec.h"

namespace deepsea {

class SchemaError;

namespace yaml {

/// A value with where it came from: its key path and the best line to report.
struct Field {
    YAML::Node node;
    YAML::Mark mark;      ///< where the value starts: for errors in the value
    std::string path;     ///< "rig.lights[0].position"; empty for the document root
    YAML::Mark key_mark;  ///< the line of its key (or list item): for errors about the whole
                          ///< value, such as a missing key inside it
};

/// 1-based line of a mark (1 for a null mark).
int line_of(const YAML::Mark& m);

/// `parent.key`, or `key` at the top level.
std::string child_path(const std::string& parent, const std::string& key);

/// One parsed document. Remembers the line of every value handed out, so that a SchemaError
/// found after parsing (a range check on the finished struct) is reported at its line too.
class Document {
public:
    /// Parses text; file names it in messages. ConfigError "file:line: YAML syntax error: ..".
    Document(const std::string& text, std::string file);
    /// Reads and parses a file: IoError if it is missing, a folder or unreadable.
    static Document load(const std::string& path);

    const std::string& file() const { return m_file; }
    /// True for an empty document (only comments, or nothing).
    bool empty() const { return m_root.node.IsNull(); }
    const Field& root() const { return m_root; }

    [[noreturn]] void fail(const YAML::Mark& mark, const std::string& path,
                           const std::string& problem) const;
    [[noreturn]] void fail(const Field& f, const std::string& problem) const {
        fail(f.mark, f.path, problem);
    }
    /// Reports a schema range error at the line of the value it names, or of the nearest
    /// enclosing value that was read (a derived value has no line of its own).
    [[noreturn]] void fail(const SchemaError& e) const;

    /// A finite number; a quoted scalar ("1.0") is a string, not a number.
    double number(const Field& f) const;
    int integer(const Field& f) const;
    bool boolean(const Field& f) const;
    /// Any scalar, as written.
    std::string string(const Field& f) const;
    std::vector<Field> list(const Field& f) const;
    /// Exactly n numbers.
    std::vector<double> numbers(const Field& f, std::size_t n, const char* what) const;
    Vec3 vec3(const Field& f) const;
    Rgb rgb(const Field& f) const;

    /// A Field for a value read by the caller (remembered for fail(SchemaError)).
    Field field(const YAML::Node& value, const YAML::Mark& key, std::string path) const;

private:
    std::string m_file;
    Field m_root;
    mutable std::map<std::string, YAML::Mark> m_marks;
};

/// The keys of one YAML map, checked against the allowed set: unknown and repeated keys are
/// errors (yaml-cpp itself silently keeps only one of two equal keys).
class MapView {
public:
    /// allowed: the keys it may hold; nullopt: any key (foreign formats such as
    /// DeepSeaRenderer's, whose keys deepsea does not all know).
    MapView(const Document& doc, const Field& f,
            const std::optional<std::vector<std::string>>& allowed);

    bool has(const std::string& key) const { return m_entries.count(key) != 0; }
    const Field& field() const { return m_field; }
    /// A required key: missing is reported at the line of the enclosing map's key.
    const Field& need(const std::string& key) const;
    const Field* opt(const std::string& key) const;
    /// The keys present, in file order.
    const std::vector<std::string>& keys() const { return m_order; }

private:
    const Document& m_doc;
    Field m_field;
    std::optional<std::vector<std::string>> m_allowed;
    std::map<std::string, Field> m_entries;
    std::vector<std::string> m_order;
};

/// "a, b, c".
std::string join(const std::vector<std::string>& v, const char* sep = ", ");

/// Shortest text that reads back to exactly v (messages and writers).
std::string fmt(double v);

}  // namespace yaml
}  // namespace deepsea
