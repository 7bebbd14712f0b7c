// The stress suite's outputs (eval/stress_case.h): one CSV row per case, and a Markdown report
// with the success rate per law and Poisson's ratio, per other axis, the strain the cases
// reached, and the list of failures with their reasons.
#pragma once

#include "eval/stress_case.h"

#include <filesystem>
#include <string>
#include <vector>

namespace hapstate {

// Throws EnvironmentError naming the file if it cannot be written.
void write_stress_csv(const std::vector<StressOutcome>& outcomes,
                      const std::filesystem::path& file);

std::string stress_markdown(const std::vector<StressOutcome>& outcomes);

}  // namespace hapstate
