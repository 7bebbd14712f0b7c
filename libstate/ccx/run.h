// Running the CalculiX solver on a deck written by write_ccx_deck.
#pragma once

#include <filesystem>

namespace hapstate {

// Runs `ccx -i problem` in `dir` (a deck written by write_ccx_deck), output to dir/ccx.log.
// The executable is $HAPSTATE_CCX if set, else `ccx` from PATH. Blocks until ccx ends.
// Throws InputError if ccx is missing, fails or reports an error; the message names the log.
void run_ccx(const std::filesystem::path& dir);

}  // namespace hapstate
