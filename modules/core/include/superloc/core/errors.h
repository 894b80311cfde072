// Error text for the command line: every app reports a failure as one line (doc/design.md#9-command-line).
#pragma once

#include <exception>
#include <string>

namespace superloc {

/// The reason of an exception as one line. mrpt::exception_to_str() frames messages with
/// "==== (non-)MRPT exception ====" lines and appends MRPT's call trace; this keeps the first
/// line with content, without frames, a "Message:" prefix or surrounding blanks.
std::string oneLineError(const std::exception& e);

}  // namespace superloc
