// `grainlift schema [--markdown]`: the output file's schema table (result_schema.h), as plain
// text or as the Markdown that docs/schema.md embeds.
#include <fmt/format.h>

#include "commands.h"
#include "grainlift/shared/errors.h"
#include "grainlift/shared/results/result_schema.h"

namespace grainlift::app {

int cmd_schema(bool markdown) {
  fmt::print("{}", markdown ? schema_markdown() : schema_text());
  return exit_success;
}

}  // namespace grainlift::app
