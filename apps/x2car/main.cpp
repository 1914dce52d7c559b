#include "apps/x2car/cli.hpp"

int main(int argc, char** argv) { return x2car::cli::run_cli(argc, argv); }
