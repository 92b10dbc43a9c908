#pragma once
/// \file The library's typed exceptions. The library throws and never exits; the CLI's main
/// maps each type to an exit code and prints what() as one line.

#include <cstddef>
#include <stdexcept>
#include <string>

namespace deepsea {

/// A third-party message made fit for a one-line error: control characters and runs of
/// blanks become one space, and it is cut to max_chars (a damaged file can make a library
/// report a name gigabytes long).
std::string one_line(const std::string& text, std::size_t max_chars = 240);

/// The shortest text that reads back to exactly v, for numbers in messages (std::to_string
/// prints 1e-300 as 0.000000).
std::string short_number(double v);

/// Base of every deepsea exception.
class Error : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
    /// Process exit code the CLI uses for this kind of failure.
    virtual int exit_code() const { return 1; }
};

/// A configuration value is unknown, missing, of the wrong type or out of range.
/// The message names the file, the line and the key.
class ConfigError : public Error {
public:
    using Error::Error;
    int exit_code() const override { return 2; }
};

/// Input data is unusable: sizes differ, a depth file has several channels and none was chosen.
class InputError : public Error {
public:
    using Error::Error;
    int exit_code() const override { return 3; }
};

/// A file cannot be read or written (missing, corrupt, unwritable, disk full).
class IoError : public Error {
public:
    using Error::Error;
    int exit_code() const override { return 4; }
};

/// A baked asset is foreign, truncated, of an unknown format, or made for another camera.
class AssetError : public Error {
public:
    using Error::Error;
    int exit_code() const override { return 5; }
};

}  // namespace deepsea

namespace deepsea {

/// Some frames of a sequence failed (each already reported); the others were written.
class FramesFailed : public Error {
public:
    using Error::Error;
    int exit_code() const override { return 6; }
};

}  // namespace deepsea

namespace deepsea {

/// A bake asked for a strict accuracy check (`deepsea bake --strict-check`) missed the bar; no
/// asset was written.
class AccuracyError : public Error {
public:
    using Error::Error;
    int exit_code() const override { return 7; }
};

}  // namespace deepsea

namespace deepsea {

/// The work needs more memory than the machine gives (std::bad_alloc, named): exit code 8.
/// Inputs and settings are size-checked before work, so this is what is left when the machine
/// is smaller than those limits allow.
class OutOfMemory : public Error {
public:
    using Error::Error;
    int exit_code() const override { return 8; }
};

}  // namespace deepsea

namespace deepsea {

/// Throws the deepsea error whose exit_code() is `exit_code` (Error for a code no kind has),
/// with `message`: an error kept as text and code (a sequence's failed frame) thrown again as
/// what it was.
[[noreturn]] void throw_error(int exit_code, const std::string& message);

}  // namespace deepsea
