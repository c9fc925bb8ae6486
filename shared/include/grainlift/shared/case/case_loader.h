// Reads a case file, applies --set overrides and validates everything against the key
// registry (case_keys.h). Every problem becomes a line "FILE:LINE: message (accepted: ...)"
// and all of them are reported together in one InputError (exit code 2).
#pragma once

#include <string>
#include <vector>

#include "grainlift/shared/case/case_model.h"

namespace grainlift {

/// @brief Load and validate a case file.
/// @param path      TOML file; unreadable files are an InputError.
/// @param overrides "section.key=value" strings (value in TOML syntax; a bare word is a string),
///                  applied in order after the file, so the last one wins.
Case load_case(const std::string& path, const std::vector<std::string>& overrides = {});

/// @brief Same as load_case, from text already in memory; @p name is used in messages.
Case parse_case(const std::string& text, const std::string& name,
                const std::vector<std::string>& overrides = {});

/// FNV-1a 64-bit hash of a string (offset basis 14695981039346656037), as 16 hex digits: the
/// case hash and the calibration cache's keys and checksums.
std::string fnv1a64_hex(const std::string& text);

}  // namespace grainlift
