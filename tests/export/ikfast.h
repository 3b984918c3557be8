// The IKFast 61 interface an IKFast solver file is compiled against, declared here for the
// tests in our own words: the solution types MoveIt's plugin hands to ComputeIk and the
// functions it calls. Only what a solver and its caller need.
#ifndef ARMIK_TEST_IKFAST_H
#define ARMIK_TEST_IKFAST_H

#include <list>
#include <stdexcept>
#include <vector>

#define IKFAST_VERSION 61

namespace ikfast {

// One joint of a solution: its value is fmul * free[freeind] + foffset (freeind < 0: foffset).
template <typename T>
struct IkSingleDOFSolutionBase {
  IkSingleDOFSolutionBase() : fmul(0), foffset(0), freeind(-1), jointtype(0x01), maxsolutions(1) {
    for (int i = 0; i < 5; i++) indices[i] = 255;
  }
  T fmul, foffset;
  signed char freeind;
  unsigned char jointtype;
  unsigned char maxsolutions;
  unsigned char indices[5];
};

template <typename T>
class IkSolutionBase {
 public:
  virtual ~IkSolutionBase() {}
  virtual void GetSolution(T* solution, const T* freevalues) const = 0;
  virtual const std::vector<int>& GetFree() const = 0;
  virtual int GetDOF() const = 0;
};

template <typename T>
class IkSolutionListBase {
 public:
  virtual ~IkSolutionListBase() {}
  virtual size_t AddSolution(const std::vector<IkSingleDOFSolutionBase<T> >& joints,
                             const std::vector<int>& free) = 0;
  virtual const IkSolutionBase<T>& GetSolution(size_t index) const = 0;
  virtual size_t GetNumSolutions() const = 0;
  virtual void Clear() = 0;
};

template <typename T>
class IkSolution : public IkSolutionBase<T> {
 public:
  IkSolution(const std::vector<IkSingleDOFSolutionBase<T> >& joints, const std::vector<int>& free)
      : joints_(joints), free_(free) {}
  void GetSolution(T* solution, const T* freevalues) const {
    for (size_t i = 0; i < joints_.size(); i++)
      solution[i] = joints_[i].freeind < 0
                        ? joints_[i].foffset
                        : freevalues[joints_[i].freeind] * joints_[i].fmul + joints_[i].foffset;
  }
  const std::vector<int>& GetFree() const { return free_; }
  int GetDOF() const { return static_cast<int>(joints_.size()); }

 private:
  std::vector<IkSingleDOFSolutionBase<T> > joints_;
  std::vector<int> free_;
};

template <typename T>
class IkSolutionList : public IkSolutionListBase<T> {
 public:
  size_t AddSolution(const std::vector<IkSingleDOFSolutionBase<T> >& joints,
                     const std::vector<int>& free) {
    list_.push_back(IkSolution<T>(joints, free));
    return list_.size() - 1;
  }
  const IkSolutionBase<T>& GetSolution(size_t index) const {
    if (index >= list_.size()) throw std::runtime_error("no such solution");
    typename std::list<IkSolution<T> >::const_iterator it = list_.begin();
    for (size_t i = 0; i < index; i++) ++it;
    return *it;
  }
  size_t GetNumSolutions() const { return list_.size(); }
  void Clear() { list_.clear(); }

 private:
  std::list<IkSolution<T> > list_;
};

}  // namespace ikfast

#ifdef IKFAST_HAS_LIBRARY
#define IKFAST_API

#ifdef IKFAST_REAL
typedef IKFAST_REAL IkReal;
#else
typedef double IkReal;
#endif

IKFAST_API bool ComputeIk(const IkReal* eetrans, const IkReal* eerot, const IkReal* pfree,
                          ikfast::IkSolutionListBase<IkReal>& solutions);
IKFAST_API void ComputeFk(const IkReal* joints, IkReal* eetrans, IkReal* eerot);
IKFAST_API int GetNumFreeParameters();
IKFAST_API int* GetFreeParameters();
IKFAST_API int GetNumJoints();
IKFAST_API int GetIkRealSize();
IKFAST_API const char* GetIkFastVersion();
IKFAST_API int GetIkType();
IKFAST_API const char* GetKinematicsHash();
#endif

#endif
