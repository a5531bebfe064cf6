// bemsurg/io/action_script.hpp: reading an action script (docs/actions.md) into the haptics module's
// ActionScript (bemsurg/haptics/action_script.hpp). The reader is JSON and lives in bemsurg::bemsurg,
// so a device program that builds its scripts in code links no JSON (docs/design.md, "Module order").
//
// Every error is a SceneError whose message starts with the file and the JSON key path at fault,
// e.g. "probe.json: actions[3].depth: expected a number, got a string" or
// "probe.json: actions[2].tool: no tool named 'grasper' (tools: probe, retractor)".
#pragma once

#include <string>

#include "bemsurg/haptics/action_script.hpp"

namespace bemsurg {

/// Reads and checks a script file. Throws SceneError naming the file and key path at fault: not
/// JSON, wrong "format" or "version", a missing or mistyped key, an unknown tool or action type,
/// an action a tool cannot do (a sphere cannot pinch), overlapping actions of one tool, a zero
/// direction, a negative time, depth or duration.
ActionScript load_action_script(const std::string& path);

/// The same from JSON text in memory; `name` stands for the file in messages.
ActionScript load_action_script_from_string(const std::string& json_text, const std::string& directory = ".",
                                            const std::string& name = "<actions>");

}  // namespace bemsurg
