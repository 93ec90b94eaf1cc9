#include "apps/common_flags.h"

DEFINE_string(config, "", "YAML file with settings (see configs/)");
DEFINE_bool(dump_config, false,
            "print the effective configuration as YAML and exit");
DEFINE_string(report, "", "write a JSON report to this file");
DEFINE_string(plot, "", "write plots (PNG/SVG) into this directory");
DEFINE_string(gt, "", "ground-truth trajectory to evaluate the result against");
