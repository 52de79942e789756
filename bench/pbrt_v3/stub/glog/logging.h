// Minimal stand-in for glog, enough to build pbrt-v3 without its submodules.
#ifndef PBRT_GLOG_STUB_H
#define PBRT_GLOG_STUB_H
#include <cstdlib>
#include <iostream>
#include <sstream>
#include <string>
namespace google {
inline void InitGoogleLogging(const char *) {}
struct LogMessage {
    std::ostringstream s; bool fatal, on;
    LogMessage(const char *f, int l, int sev, bool enabled) : fatal(sev >= 3), on(enabled) {
        if (on) s << "[" << f << ":" << l << "] ";
    }
    ~LogMessage() { if (on && (fatal || stub_sev >= 1)) std::cerr << s.str() << std::endl; if (fatal) std::abort(); }
    std::ostream &stream() { return s; }
    int stub_sev = 1;
};
struct Voidify { void operator&(std::ostream &) {} };
}
extern int FLAGS_minloglevel, FLAGS_stderrthreshold, FLAGS_v;
extern bool FLAGS_logtostderr;
extern std::string FLAGS_log_dir;
#define GLOG_STUB_INFO 0
#define GLOG_STUB_WARNING 1
#define GLOG_STUB_ERROR 2
#define GLOG_STUB_FATAL 3
#define LOG(sev) (GLOG_STUB_##sev < 1) ? (void)0 : google::Voidify() & google::LogMessage(__FILE__, __LINE__, GLOG_STUB_##sev, true).stream()
#define VLOG(n) true ? (void)0 : google::Voidify() & google::LogMessage(__FILE__, __LINE__, 0, false).stream()
#define CHECK(c) (c) ? (void)0 : google::Voidify() & google::LogMessage(__FILE__, __LINE__, 3, true).stream() << "Check failed: " #c " "
#define CHECK_OP_(a, b, op) CHECK((a) op (b))
#define CHECK_EQ(a, b) CHECK_OP_(a, b, ==)
#define CHECK_NE(a, b) CHECK_OP_(a, b, !=)
#define CHECK_LT(a, b) CHECK_OP_(a, b, <)
#define CHECK_LE(a, b) CHECK_OP_(a, b, <=)
#define CHECK_GT(a, b) CHECK_OP_(a, b, >)
#define CHECK_GE(a, b) CHECK_OP_(a, b, >=)
#define DCHECK(c) while (false) CHECK(c)
#define DCHECK_EQ(a, b) while (false) CHECK_EQ(a, b)
#define DCHECK_NE(a, b) while (false) CHECK_NE(a, b)
#define DCHECK_LT(a, b) while (false) CHECK_LT(a, b)
#define DCHECK_LE(a, b) while (false) CHECK_LE(a, b)
#define DCHECK_GT(a, b) while (false) CHECK_GT(a, b)
#define DCHECK_GE(a, b) while (false) CHECK_GE(a, b)
#endif
