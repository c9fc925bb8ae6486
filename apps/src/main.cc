// grainlift: the command line. Parses arguments and hands the work to the modules; no physics.
#include "commands.h"

int main(int argc, char** argv) { return grainlift::app::main_with_args(argc, argv); }
