#include <glog/logging.h>
int FLAGS_minloglevel = 0, FLAGS_stderrthreshold = 2, FLAGS_v = 0;
bool FLAGS_logtostderr = false;
std::string FLAGS_log_dir;
