#include "cli.h"

int main(int argc, char** argv) { return plugslam::runtime::runCli(argc, argv); }
