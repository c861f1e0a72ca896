// Exceptions thrown at I/O and configuration boundaries. Messages carry their context.
#pragma once

#include <stdexcept>
#include <string>

namespace beamtrace {

/// Base of all beamtrace errors.
class Error : public std::runtime_error {
  public:
    using std::runtime_error::runtime_error;
};

/// A file could not be read or parsed: the message names the file (and line where known).
class InputError : public Error {
  public:
    InputError(const std::string& path, const std::string& what)
        : Error(path + ": " + what), path_(path) {}
    InputError(const std::string& path, long line, const std::string& what)
        : Error(path + ":" + std::to_string(line) + ": " + what), path_(path) {}
    [[nodiscard]] const std::string& path() const { return path_; }

  private:
    std::string path_;
};

/// Impossible or inconsistent settings; the message lists every problem found.
class ConfigError : public Error {
  public:
    using Error::Error;
};

/// An output could not be written.
class OutputError : public Error {
  public:
    using Error::Error;
};

/// A call was stopped by its CancelToken (core/cancel.hpp) before it finished. Nothing it was
/// writing was written: its temporary files are removed as the exception unwinds.
class Interrupted : public Error {
  public:
    /// `what`: the call ("survey", "scan"...); `reason`: the token's (the CLI: the signal).
    Interrupted(const std::string& what, int reason)
        : Error(what + ": interrupted; nothing was written"), reason_(reason) {}
    [[nodiscard]] int reason() const { return reason_; }

  private:
    int reason_ = 0;
};

}  // namespace beamtrace
