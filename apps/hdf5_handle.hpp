#pragma once
// RAII for the HDF5 C API, shared by the writer (h5out.cpp) and the reader (h5in.cpp): one owner per
// hid_t, closed by the matching H5?close; and a guard that silences HDF5's own error printing while
// slipfront reports errors itself. Each user names its error type and message prefix:
//   using Hid = HdfHandle<OutputError, hdf5_cannot>;   // throws OutputError("HDF5: cannot " + what)
#include <hdf5.h>

#include <string>
#include <utility>

namespace slipfront::app {

template <class Error, const char* Prefix>
class HdfHandle {
 public:
  using Closer = herr_t (*)(hid_t);
  HdfHandle(hid_t id, Closer closer, const std::string& what) : id_(id), close_(closer) {
    if (id_ < 0) throw Error(Prefix + what);
  }
  HdfHandle(const HdfHandle&) = delete;
  HdfHandle& operator=(const HdfHandle&) = delete;
  HdfHandle(HdfHandle&& o) noexcept : id_(std::exchange(o.id_, -1)), close_(o.close_) {}
  ~HdfHandle() {
    if (id_ >= 0) close_(id_);
  }
  hid_t get() const { return id_; }
  /// Closes now and reports failure (for a file: flushing happens here).
  void close(const std::string& what) {
    const hid_t id = std::exchange(id_, -1);
    if (id >= 0 && close_(id) < 0) throw Error(Prefix + what);
  }

 private:
  hid_t id_;
  Closer close_;
};

/// Silences HDF5's own error printing for its lifetime (errors are reported by slipfront).
class QuietHdf5 {
 public:
  QuietHdf5() {
    H5Eget_auto2(H5E_DEFAULT, &func_, &data_);
    H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  }
  ~QuietHdf5() { H5Eset_auto2(H5E_DEFAULT, func_, data_); }
  QuietHdf5(const QuietHdf5&) = delete;
  QuietHdf5& operator=(const QuietHdf5&) = delete;

 private:
  H5E_auto2_t func_ = nullptr;
  void* data_ = nullptr;
};

}  // namespace slipfront::app
