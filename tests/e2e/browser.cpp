#include "tests/e2e/browser.h"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <spawn.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cctype>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <stdexcept>
#include <thread>

extern char** environ;

namespace nightcap::test {
namespace {
namespace fs = std::filesystem;
using nlohmann::json;
using Clock = std::chrono::steady_clock;

constexpr auto kTimeout = std::chrono::seconds(60);

std::string file_url(const fs::path& file) {
  static const char* hex = "0123456789ABCDEF";
  std::string url = "file://";
  for (const unsigned char c : fs::absolute(file).lexically_normal().string()) {
    if (std::isalnum(c) || std::strchr("-._~/", c)) {
      url += static_cast<char>(c);
    } else {
      url += '%';
      url += hex[c >> 4];
      url += hex[c & 15];
    }
  }
  return url;
}

std::string base64_decode(const std::string& text) {
  static const char* alphabet = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string bytes;
  unsigned bits = 0;
  int count = 0;
  for (const char c : text) {
    const char* at = std::strchr(alphabet, c);
    if (c == '\0' || !at) continue;  // '=' padding
    bits = (bits << 6) | static_cast<unsigned>(at - alphabet);
    if ((count += 6) >= 8) {
      count -= 8;
      bytes += static_cast<char>((bits >> count) & 0xff);
    }
  }
  return bytes;
}

// A CDP RemoteObject (a console argument, a thrown value) as DevTools would print it.
std::string remote_text(const json& object) {
  if (object.contains("value")) {
    const json& value = object.at("value");
    return value.is_string() ? value.get<std::string>() : value.dump();
  }
  if (object.contains("unserializableValue")) return object.value("unserializableValue", "");
  if (object.contains("description")) {
    // An Error's description carries its stack after the first line; the location is added apart.
    const std::string description = object.value("description", "");
    return description.substr(0, description.find('\n'));
  }
  return object.value("type", "");
}

std::string location(const json& where) {
  const std::string url = where.value("url", "");
  if (url.empty()) return "";
  // CDP's line numbers count from 0.
  return " (" + url + (where.contains("lineNumber") ? ":" + std::to_string(where.value("lineNumber", 0) + 1) : "") +
         ")";
}

// One headless Chromium driven over the DevTools protocol on a socket (--remote-debugging-pipe:
// it reads fd 3 and writes fd 4, NUL-terminated JSON). The protocol, unlike --enable-logging's
// stderr, tells console.error from console.log and reports failed resource loads.
class Browser {
 public:
  explicit Browser(const fs::path& scratch) : deadline_(Clock::now() + kTimeout) {
    const fs::path profile = scratch / "chromium-profile";
    fs::remove_all(profile);
    fs::create_directories(profile);
    stderr_file_ = scratch / "chromium.stderr";

    int pair[2];
    if (::socketpair(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0, pair) != 0)
      throw std::runtime_error(std::string("socketpair: ") + std::strerror(errno));
    socket_ = pair[0];
    // Above 4, so that dup2 onto 3 and 4 always makes new descriptors, which exec keeps.
    const int theirs = ::fcntl(pair[1], F_DUPFD_CLOEXEC, 10);
    ::close(pair[1]);
    if (theirs < 0) {
      ::close(socket_);
      throw std::runtime_error(std::string("fcntl: ") + std::strerror(errno));
    }

    const std::string user_data = "--user-data-dir=" + profile.string();
    const std::vector<std::string> args = {
        kChromium.string(), "--headless",        "--no-sandbox", "--disable-gpu",
        "--no-first-run",   "--hide-scrollbars", user_data,      "--remote-debugging-pipe",
        "about:blank"};
    std::vector<char*> argv;
    for (const std::string& arg : args) argv.push_back(const_cast<char*>(arg.c_str()));
    argv.push_back(nullptr);

    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, 0, "/dev/null", O_RDONLY, 0);
    posix_spawn_file_actions_addopen(&actions, 1, "/dev/null", O_WRONLY, 0);
    posix_spawn_file_actions_addopen(&actions, 2, stderr_file_.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    posix_spawn_file_actions_adddup2(&actions, theirs, 3);
    posix_spawn_file_actions_adddup2(&actions, theirs, 4);
    posix_spawnattr_t attributes;
    posix_spawnattr_init(&attributes);
    // Its own process group, so that a hung browser is killed with its renderers.
    posix_spawnattr_setflags(&attributes, POSIX_SPAWN_SETPGROUP | POSIX_SPAWN_SETSIGMASK);
    posix_spawnattr_setpgroup(&attributes, 0);
    sigset_t none;
    sigemptyset(&none);
    posix_spawnattr_setsigmask(&attributes, &none);
    const int error = ::posix_spawn(&pid_, argv[0], &actions, &attributes, argv.data(), environ);
    posix_spawn_file_actions_destroy(&actions);
    posix_spawnattr_destroy(&attributes);
    ::close(theirs);
    if (error != 0) {
      ::close(socket_);
      pid_ = -1;
      throw std::runtime_error("cannot run " + kChromium.string() + ": " + std::strerror(error));
    }
  }

  Browser(const Browser&) = delete;
  Browser& operator=(const Browser&) = delete;

  ~Browser() {
    if (!failed_) {
      try {
        send("Browser.close", json::object(), false);
      } catch (const std::exception&) {
      }
    }
    // Chromium also quits when its end of the socket closes; one that failed is not waited for.
    ::close(socket_);
    const auto give_up = Clock::now() + std::chrono::seconds(failed_ ? 0 : 5);
    while (Clock::now() < give_up) {
      siginfo_t info{};
      if (::waitid(P_PID, pid_, &info, WEXITED | WNOHANG | WNOWAIT) != 0 || info.si_pid != 0) break;
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    // The browser is not reaped yet, so its group's id cannot have been reused.
    ::kill(-pid_, SIGKILL);
    ::waitpid(pid_, nullptr, 0);
  }

  // Opens a tab that reports to this session, then loads `url` in it.
  void open(const std::string& url, int width = 0, int height = 0) {
    const auto target = call("Target.createTarget", {{"url", "about:blank"}}, false)["targetId"].get<std::string>();
    session_ =
        call("Target.attachToTarget", {{"targetId", target}, {"flatten", true}}, false)["sessionId"].get<std::string>();
    // Enabled before navigating, so that nothing the page logs while loading is missed.
    call("Runtime.enable");
    call("Log.enable");
    if (width > 0)
      call("Emulation.setDeviceMetricsOverride",
           {{"width", width}, {"height", height}, {"deviceScaleFactor", 1}, {"mobile", false}});
    const json navigated = call("Page.navigate", {{"url", url}});
    if (navigated.contains("errorText")) fail("cannot load " + url + ": " + navigated["errorText"].get<std::string>());
  }

  // The value of a JavaScript expression in the page; a promise is awaited.
  json evaluate(const std::string& expression) {
    const json result =
        call("Runtime.evaluate", {{"expression", expression}, {"awaitPromise", true}, {"returnByValue", true}});
    if (result.contains("exceptionDetails")) fail("the page check threw: " + result["exceptionDetails"].dump());
    return result.at("result").value("value", json());
  }

  // The result of a protocol command; the events read meanwhile are kept in events().
  json call(const std::string& method, const json& params = json::object(), bool in_page = true) {
    const int id = send(method, params, in_page);
    for (;;) {
      json message = read_message();
      if (message.value("id", -1) == id) {
        if (message.contains("error")) fail(method + ": " + message["error"].dump());
        return message.value("result", json::object());
      }
      if (message.contains("method")) events_.push_back(std::move(message));
    }
  }

  const std::vector<json>& events() const { return events_; }

  [[noreturn]] void fail(const std::string& why) {
    failed_ = true;
    std::ifstream in(stderr_file_, std::ios::binary);
    std::ostringstream err;
    err << in.rdbuf();
    std::string text = err.str();
    if (text.size() > 4000) text = "..." + text.substr(text.size() - 4000);
    throw std::runtime_error(why + "\nchromium's stderr (" + stderr_file_.string() + "):\n" + text);
  }

 private:
  int send(const std::string& method, const json& params, bool in_page) {
    json message = {{"id", ++next_id_}, {"method", method}, {"params", params}};
    if (in_page) message["sessionId"] = session_;
    const std::string text = message.dump() + '\0';
    for (size_t sent = 0; sent < text.size();) {
      // MSG_NOSIGNAL: a browser that died fails the call instead of killing the test with SIGPIPE.
      const ssize_t n = ::send(socket_, text.data() + sent, text.size() - sent, MSG_NOSIGNAL);
      if (n < 0 && errno == EINTR) continue;
      if (n < 0) fail("Chromium stopped reading (" + method + "): " + std::strerror(errno));
      sent += static_cast<size_t>(n);
    }
    return next_id_;
  }

  json read_message() {
    for (;;) {
      const size_t end = buffer_.find('\0');
      if (end != std::string::npos) {
        json message = json::parse(buffer_.substr(0, end));
        buffer_.erase(0, end + 1);
        return message;
      }
      const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline_ - Clock::now()).count();
      pollfd ready = {socket_, POLLIN, 0};
      const int polled = left > 0 ? ::poll(&ready, 1, static_cast<int>(left)) : 0;
      if (polled < 0 && errno == EINTR) continue;
      if (polled == 0) fail("Chromium did not answer within " + std::to_string(kTimeout.count()) + " s");
      char chunk[65536];
      const ssize_t n = ::recv(socket_, chunk, sizeof chunk, 0);
      if (n < 0 && errno == EINTR) continue;
      if (n <= 0) fail("Chromium exited");
      buffer_.append(chunk, static_cast<size_t>(n));
    }
  }

  Clock::time_point deadline_;
  fs::path stderr_file_;
  int socket_ = -1;
  pid_t pid_ = -1;
  int next_id_ = 0;
  bool failed_ = false;
  std::string session_, buffer_;
  std::vector<json> events_;
};

// Resolves once `load` has fired and its handlers (and the microtasks they queue) have run.
constexpr const char* kAfterLoad = R"(new Promise(done => {
  const after = () => setTimeout(done, 0);
  if (document.readyState === 'complete') after(); else addEventListener('load', after, {once: true});
}))";

constexpr const char* kCollect = R"(({
  url: location.href,
  title: document.title,
  sections: Array.from(document.querySelectorAll('section.pass'), s => {
    const box = s.getBoundingClientRect();
    return {pass: s.getAttribute('data-pass') ?? '', width: box.width, height: box.height};
  }),
  images: Array.from(document.images, i => ({
    src: i.getAttribute('src') ?? '', natural_width: i.naturalWidth, natural_height: i.naturalHeight,
    complete: i.complete
  }))
}))";

void require_file(const fs::path& html) {
  if (!fs::is_regular_file(html)) throw std::runtime_error(html.string() + ": no such file");
}

}  // namespace

PageCheck check_page(const fs::path& html, const fs::path& scratch, const std::string& script) {
  require_file(html);
  Browser browser(scratch);
  browser.open(file_url(html));
  browser.evaluate(kAfterLoad);
  const json script_result = script.empty() ? json() : browser.evaluate(script);
  const json page = browser.evaluate(kCollect);
  // Guards against having read the blank tab, should the navigation not have committed yet.
  if (!page.is_object() || page.value("url", "").rfind("file:", 0) != 0)
    browser.fail("the page never reported: " + page.dump());

  PageCheck check;
  check.title = page.at("title").get<std::string>();
  check.script_result = script_result;
  for (const json& s : page.at("sections"))
    check.sections.push_back(
        {s.at("pass").get<std::string>(), s.at("width").get<double>(), s.at("height").get<double>()});
  for (const json& i : page.at("images"))
    check.images.push_back({i.at("src").get<std::string>(), i.at("natural_width").get<int>(),
                            i.at("natural_height").get<int>(), i.at("complete").get<bool>()});

  for (const json& event : browser.events()) {
    const auto method = event.at("method").get<std::string>();
    const json params = event.value("params", json::object());
    if (method == "Runtime.consoleAPICalled") {
      const auto type = params.value("type", "");
      if (type != "error" && type != "assert") continue;
      std::string text = "console." + type + ":";
      for (const json& arg : params.value("args", json::array())) text += " " + remote_text(arg);
      const json frames = params.value("stackTrace", json::object()).value("callFrames", json::array());
      check.console_errors.push_back(text + (frames.empty() ? "" : location(frames[0])));
    } else if (method == "Runtime.exceptionThrown") {
      const json details = params.value("exceptionDetails", json::object());
      std::string text = details.value("text", "Uncaught");
      if (details.contains("exception")) text += " " + remote_text(details.at("exception"));
      check.console_errors.push_back(text + location(details));
    } else if (method == "Log.entryAdded") {
      // Failed loads ("Failed to load resource: net::ERR_FILE_NOT_FOUND") and the browser's own
      // errors, such as blocked content.
      const json entry = params.value("entry", json::object());
      if (entry.value("level", "") == "error")
        check.console_errors.push_back(entry.value("text", "") + location(entry));
    }
  }
  return check;
}

void screenshot_page(const fs::path& html, const fs::path& png, int width, int height, const fs::path& scratch) {
  require_file(html);
  Browser browser(scratch);
  browser.open(file_url(html), width, height);
  browser.evaluate(kAfterLoad);
  const json shot = browser.call("Page.captureScreenshot", {{"format", "png"}});
  std::ofstream out(png, std::ios::binary | std::ios::trunc);
  out << base64_decode(shot.value("data", ""));
  if (!out.flush()) throw std::runtime_error(png.string() + ": cannot write");
}

}  // namespace nightcap::test
