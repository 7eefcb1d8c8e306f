// masssprings_trace.h: writes the quantities of your solution of the
// mass-spring assignment (github.com/alecjacobson/computer-graphics-mass-spring-systems)
// into the folder `masssprings trace --compare` reads, one Matrix Market file
// each, 17 significant digits. Eigen only; one header, nothing to link.
//
//     masssprings trace --cpp-header > include/masssprings_trace.h
//
// Add one line per quantity where your code computes it:
//
//   fast_mass_springs_precomputation_sparse (after each is made):
//     masssprings_trace::write("r", r);   masssprings_trace::write("M", M);
//     masssprings_trace::write("A", A);   masssprings_trace::write("C", C);
//     masssprings_trace::write("Q", Q);
//     prefactorization.compute(Q);
//     masssprings_trace::write_factor(prefactorization);      // P.mtx and L.mtx
//
//   fast_mass_springs_step_sparse:
//     masssprings_trace::start_step(Uprev, Ucur);             // first line: counts the steps
//     masssprings_trace::write("y", y);
//     for(int iter = 0; iter < 50; iter++) {
//       ... masssprings_trace::write("d", d);                 // d_1, d_2, ... in turn
//       ... masssprings_trace::write("b", b);
//       ... masssprings_trace::write("p", p);
//     }
//
// and run your program with
//
//   MASSSPRINGS_TRACE_DIR=mine        the folder to write (nothing is written without it)
//   MASSSPRINGS_TRACE_STEP=3          the step to write (from 1; 3 unless said)
//   MASSSPRINGS_TRACE_ITERATIONS=2    its iterations to write (2 unless said)
//   MASSSPRINGS_TRACE_FRAMES=frames   optional: every step's positions, frame-000000.obj, ...
//   MASSSPRINGS_TRACE_FROM=flag-trace optional: start the traced step from our U_prev.mtx and
//                                     U_cur.mtx (needs start_step in main.cpp, below)
//
// then `masssprings trace --compare flag-trace mine`. Compare your own run
// from rest first (it exercises your loop over steps), then your step from
// our state: move the start_step line from your step to main.cpp's step
// lambda, before `const Eigen::MatrixXd U_stash = U;`, as
//     masssprings_trace::start_step(Uprev, U);
// where it may replace Uprev and U, and set MASSSPRINGS_TRACE_FROM. Count
// the steps in one place only. The dense versions (Eigen::MatrixXd,
// Eigen::LLT) are written too.
#ifndef MASSSPRINGS_TRACE_H
#define MASSSPRINGS_TRACE_H

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <Eigen/Sparse>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <map>
#include <sstream>
#include <string>
#include <vector>
#ifdef _WIN32
#include <direct.h>
#else
#include <sys/stat.h>
#endif

namespace masssprings_trace
{
  // What the environment asks, read once.
  struct Settings
  {
    std::string dir, frames, from;
    int step = 3, iterations = 2;
  };

  inline std::string environment(const char * name)
  {
    const char * value = std::getenv(name);
    return value ? std::string(value) : std::string();
  }

  inline int whole(const char * name, int otherwise)
  {
    const std::string text = environment(name);
    return text.empty() ? otherwise : std::atoi(text.c_str());
  }

  inline void make_folder(const std::string & folder)
  {
    if(folder.empty()) return;
#ifdef _WIN32
    _mkdir(folder.c_str());
#else
    mkdir(folder.c_str(), 0755);
#endif
  }

  inline const Settings & settings()
  {
    static const Settings s = []()
    {
      Settings s;
      s.dir = environment("MASSSPRINGS_TRACE_DIR");
      s.frames = environment("MASSSPRINGS_TRACE_FRAMES");
      s.from = environment("MASSSPRINGS_TRACE_FROM");
      s.step = whole("MASSSPRINGS_TRACE_STEP", 3);
      s.iterations = whole("MASSSPRINGS_TRACE_ITERATIONS", 2);
      make_folder(s.dir);
      make_folder(s.frames);
      return s;
    }();
    return s;
  }

  // The step under way (0: the precomputation) and each per-iteration
  // quantity's count in it.
  struct Progress
  {
    int step = 0;
    std::map<std::string, int> written;
  };

  inline Progress & progress()
  {
    static Progress p;
    return p;
  }

  // d, b and p are written once per iteration, as d_1, d_2, ...
  inline bool per_iteration(const std::string & name)
  {
    return name == "d" || name == "b" || name == "p";
  }

  // The path of `name` now, or "" when it is not to be written.
  inline std::string path_of(const std::string & name)
  {
    const Settings & s = settings();
    Progress & p = progress();
    if(s.dir.empty()) return "";
    const bool once = name == "r" || name == "M" || name == "A" || name == "C" ||
      name == "Q" || name == "P" || name == "L";
    if(once) return s.dir + "/" + name + ".mtx";
    if(p.step != s.step) return "";
    if(!per_iteration(name)) return s.dir + "/" + name + ".mtx";
    const int k = ++p.written[name];
    if(k > s.iterations) return "";
    return s.dir + "/" + name + "_" + std::to_string(k) + ".mtx";
  }

  inline std::ofstream open(const std::string & path)
  {
    std::ofstream out(path.c_str());
    if(!out) std::cerr << "masssprings_trace: cannot write " << path << std::endl;
    out << std::setprecision(17);
    return out;
  }

  // A dense matrix (a vector too) as an array file, column by column.
  inline void write(const std::string & name, const Eigen::MatrixXd & X)
  {
    const std::string path = path_of(name);
    if(path.empty()) return;
    std::ofstream out = open(path);
    out << "%%MatrixMarket matrix array real general\n";
    out << "% " << name << ", written by masssprings_trace.h\n";
    out << X.rows() << " " << X.cols() << "\n";
    for(int j = 0; j < X.cols(); j++)
      for(int i = 0; i < X.rows(); i++) out << X(i, j) << "\n";
  }

  // A sparse matrix as a coordinate file, every stored entry.
  inline void write(const std::string & name, const Eigen::SparseMatrix<double> & X)
  {
    const std::string path = path_of(name);
    if(path.empty()) return;
    std::ofstream out = open(path);
    out << "%%MatrixMarket matrix coordinate real general\n";
    out << "% " << name << ", written by masssprings_trace.h\n";
    out << X.rows() << " " << X.cols() << " " << X.nonZeros() << "\n";
    for(int j = 0; j < X.outerSize(); j++)
      for(Eigen::SparseMatrix<double>::InnerIterator it(X, j); it; ++it)
        out << it.row() + 1 << " " << it.col() + 1 << " " << it.value() << "\n";
  }

  // P and L of the sparse factor, L Lᵀ = P Q Pᵀ: row indices(i) of P has
  // its 1 in column i.
  inline void write_factor(const Eigen::SimplicialLLT<Eigen::SparseMatrix<double> > & f)
  {
    const Eigen::PermutationMatrix<Eigen::Dynamic, Eigen::Dynamic, int> & P = f.permutationP();
    std::vector<Eigen::Triplet<double> > ones;
    for(int i = 0; i < P.indices().size(); i++) ones.emplace_back(P.indices()(i), i, 1.0);
    Eigen::SparseMatrix<double> Pm(P.indices().size(), P.indices().size());
    Pm.setFromTriplets(ones.begin(), ones.end());
    write("P", Pm);
    const Eigen::SparseMatrix<double> L = f.matrixL();
    write("L", L);
  }

  // L of the dense factor (no ordering: --compare checks it in the
  // natural order).
  inline void write_factor(const Eigen::LLT<Eigen::MatrixXd> & f)
  {
    const Eigen::MatrixXd L = f.matrixL();
    write("L", L);
  }

  // An n × 3 array file written by `masssprings trace`.
  inline bool read_array(const std::string & path, Eigen::MatrixXd & X)
  {
    std::ifstream in(path.c_str());
    std::string line;
    while(std::getline(in, line) && (line.empty() || line[0] == '%')) {}
    std::istringstream size(line);
    int rows = 0, cols = 0;
    if(!(size >> rows >> cols)) return false;
    X.resize(rows, cols);
    for(int j = 0; j < cols; j++)
      for(int i = 0; i < rows; i++)
        if(!(in >> X(i, j))) return false;
    return true;
  }

  // The positions of a frame, one `v` line per vertex.
  inline void write_frame(int number, const Eigen::MatrixXd & U)
  {
    char name[32];
    std::snprintf(name, sizeof name, "/frame-%06d.obj", number);
    std::ofstream out = open(settings().frames + name);
    for(int i = 0; i < U.rows(); i++)
      out << "v " << U(i, 0) << " " << U(i, 1) << " " << U(i, 2) << "\n";
  }

  // The start of a step: counts it, writes the positions as a frame, and
  // at the traced step writes U_prev and U_cur.
  inline void start_step(const Eigen::MatrixXd & Uprev, const Eigen::MatrixXd & Ucur)
  {
    const Settings & s = settings();
    Progress & p = progress();
    if(!s.frames.empty()) write_frame(p.step, Ucur);
    p.step++;
    p.written.clear();
    write("U_prev", Uprev);
    write("U_cur", Ucur);
  }

  // The same from main.cpp's loop, where the state can be replaced: at the
  // traced step, by our U_prev.mtx and U_cur.mtx in MASSSPRINGS_TRACE_FROM.
  inline void start_step(Eigen::MatrixXd & Uprev, Eigen::MatrixXd & Ucur)
  {
    const Settings & s = settings();
    if(!s.from.empty() && progress().step + 1 == s.step)
    {
      Eigen::MatrixXd prev, cur;
      if(read_array(s.from + "/U_prev.mtx", prev) && read_array(s.from + "/U_cur.mtx", cur) &&
        prev.rows() == Uprev.rows() && cur.rows() == Ucur.rows())
      {
        Uprev = prev;
        Ucur = cur;
      }
      else
      {
        std::cerr << "masssprings_trace: cannot read U_prev.mtx and U_cur.mtx of "
          << Ucur.rows() << " rows in " << s.from << std::endl;
      }
    }
    const Eigen::MatrixXd & prev = Uprev;
    const Eigen::MatrixXd & cur = Ucur;
    start_step(prev, cur);
  }
}

#endif
