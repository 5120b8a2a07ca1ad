#include "apps/gnuplot_figures.h"

#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace fs = std::filesystem;

namespace rlt {

namespace {

// ten colours that stay apart on white, one per run and behavior (then they repeat)
const char* const kPalette[] = {"1f77b4", "d62728", "2ca02c", "ff7f0e", "9467bd",
                                "8c564b", "e377c2", "7f7f7f", "bcbd22", "17becf"};

// a gnuplot single-quoted string ('' stands for a quote inside)
std::string quoted(const std::string& text) {
  std::string out = "'";
  for (char c : text) out += c == '\'' ? std::string("''") : std::string(1, c);
  return out + "'";
}

std::string colour(int index, bool faint) {
  // gnuplot's #AARRGGBB: AA is the transparency (00 opaque)
  return std::string("'#") + (faint ? "b0" : "") + kPalette[index % 10] + "'";
}

// gnuplot's own y range, unless every point has the same value: gnuplot would warn and pick
// [-1, 1]; a constant 0 (a rate that never rose) gets [0, 1] instead
std::string y_range(const Panel& panel) {
  double low = 0, high = 0;
  bool first = true;
  for (const Series& s : panel.series)
    for (double v : s.y) {
      low = first ? v : std::min(low, v);
      high = first ? v : std::max(high, v);
      first = false;
    }
  if (first || low != high) return "set yrange [*:*]\n";
  std::ostringstream out;
  out.precision(9);
  if (low == 0)
    out << "set yrange [0:1]\n";
  else
    out << "set yrange [" << std::min(low * 0.5, low * 1.5) << ':' << std::max(low * 0.5, low * 1.5)
        << "]\n";
  return out.str();
}

}  // namespace

std::vector<std::string> write_gnuplot_figures(const std::vector<Figure>& figures,
                                               const std::string& out_dir, bool draw_raw) {
  fs::create_directories(fs::path(out_dir) / "data");
  std::ostringstream gp;
  gp << "# Learning curves written by `rlt plot`; run again with: gnuplot plots.gp (in this "
        "folder)\n"
     << "set grid lc rgb '#dddddd'\n"
     << "set format x '%.1s%c'\n"
     << "set key outside right top\n";
  std::vector<std::string> pngs;
  for (const Figure& figure : figures) {
    const std::string data = "data/" + figure.name + ".dat";
    std::ofstream out(fs::path(out_dir) / data);
    out.precision(9);
    const int n = int(figure.panels.size());
    const int columns = std::min(n, 2), rows = (n + columns - 1) / columns;
    gp << "\nset terminal pngcairo size " << (columns == 1 ? 1000 : 1400) << ',' << 380 * rows + 40
       << " font ',10' noenhanced\n"
       << "set output " << quoted(figure.name + ".png") << "\n";
    if (n > 1) gp << "set multiplot layout " << rows << ',' << columns << "\n";
    int block = 0;
    for (const Panel& panel : figure.panels) {
      gp << y_range(panel) << "set title " << quoted(panel.title) << "\nset xlabel "
         << quoted(panel.x_label) << "\nset ylabel " << quoted(panel.y_label) << "\nplot ";
      const bool steps = figure.name == "lessons";
      for (size_t i = 0; i < panel.series.size(); ++i, ++block) {
        const Series& s = panel.series[i];
        // one block per series, two blank lines apart (gnuplot's `index`)
        for (size_t k = 0; k < s.x.size(); ++k)
          out << s.x[k] << ' ' << s.y[k] << ' ' << s.smoothed[k] << '\n';
        out << "\n\n";
        const std::string source = quoted(data) + " index " + std::to_string(block);
        if (i > 0) gp << ", \\\n     ";
        if (draw_raw && s.smoothed != s.y)
          gp << source << " using 1:2 with lines lw 1 lc rgb " << colour(s.colour, true)
             << " notitle, \\\n     ";
        gp << source << " using 1:3 with " << (steps ? "steps" : "lines") << " lw 2 lc rgb "
           << colour(s.colour, false) << " title " << quoted(s.title);
      }
      gp << "\n";
    }
    if (n > 1) gp << "unset multiplot\n";
    gp << "set output\n";
    pngs.push_back((fs::path(out_dir) / (figure.name + ".png")).string());
  }
  std::ofstream(fs::path(out_dir) / "plots.gp") << gp.str();
  return pngs;
}

namespace {

bool on_path(const std::string& program) {
  const char* path = std::getenv("PATH");
  std::stringstream dirs(path ? path : "");
  std::string dir;
  while (std::getline(dirs, dir, ':'))
    if (!dir.empty() && ::access((fs::path(dir) / program).c_str(), X_OK) == 0) return true;
  return false;
}

}  // namespace

void run_gnuplot(const std::string& out_dir) {
  if (!on_path("gnuplot"))
    throw std::runtime_error(
        "rlt plot draws with gnuplot, which is not on PATH (Debian: apt-get install gnuplot-nox)");
  const pid_t pid = ::fork();
  if (pid < 0) throw std::runtime_error("cannot start gnuplot");
  if (pid == 0) {
    if (::chdir(out_dir.c_str()) != 0) ::_exit(126);
    ::execlp("gnuplot", "gnuplot", "plots.gp", static_cast<char*>(nullptr));
    ::_exit(127);
  }
  int status = 0;
  ::waitpid(pid, &status, 0);
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0)
    throw std::runtime_error("gnuplot failed on " + (fs::path(out_dir) / "plots.gp").string() +
                             " (exit status " +
                             std::to_string(WIFEXITED(status) ? WEXITSTATUS(status) : -1) + ")");
}

}  // namespace rlt
