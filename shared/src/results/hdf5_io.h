// The HDF5 primitives the result file's writer and reader are made of (result_write.cc,
// result_read.cc): one group, attribute or dataset at a time. Private to grainlift_shared, the
// only code in grainlift that touches HDF5.
#pragma once

#include <hdf5.h>

#include <optional>
#include <string>
#include <vector>

namespace grainlift::hdf5 {

/// Owns one HDF5 identifier and closes it with the matching function.
class Handle {
 public:
  Handle(hid_t id, herr_t (*close)(hid_t)) : id_(id), close_(close) {}
  Handle(const Handle&) = delete;
  Handle& operator=(const Handle&) = delete;
  Handle(Handle&& o) noexcept : id_(o.id_), close_(o.close_) { o.id_ = -1; }
  ~Handle() {
    if (id_ >= 0) close_(id_);
  }
  operator hid_t() const { return id_; }
  bool valid() const { return id_ >= 0; }

 private:
  hid_t id_;
  herr_t (*close_)(hid_t);
};

/// @brief Throws RunError naming @p what when an HDF5 call returned @p status < 0.
void check(herr_t status, const std::string& what);

/// @brief HDF5 prints its error stack to stderr by default; grainlift reports errors itself.
void silence_hdf5();

// ---- writing ---------------------------------------------------------------------------------
/// @brief A new group @p name in @p parent.
Handle make_group(hid_t parent, const char* name);

/// @brief A fixed-length string type of @p size bytes; grainlift writes UTF-8, a reader converts
/// a file's ASCII strings only to an ASCII memory type (HDF5 converts within one character set).
Handle string_type(std::size_t size, H5T_cset_t cset = H5T_CSET_UTF8);

/// @brief A scalar string attribute.
void attr_string(hid_t obj, const char* name, const std::string& value);
/// @brief A scalar float64 attribute.
void attr_number(hid_t obj, const char* name, double value);
/// @brief A scalar int64 attribute.
void attr_number(hid_t obj, const char* name, long long value);
/// @brief A scalar string dataset.
void dataset_string(hid_t parent, const char* name, const std::string& value);
/// @brief 1D (@p ny == 0) or 2D [ny][nx] dataset of doubles with a "units" attribute.
void dataset_doubles(hid_t parent, const char* name, const std::vector<double>& v,
                     const char* units, std::size_t ny = 0, std::size_t nx = 0);

// ---- reading ---------------------------------------------------------------------------------
// Every read checks what the file declares before it allocates or reads: a file is refused
// (InputError, naming the object and what is accepted) rather than read past a buffer or
// allocated for data it does not hold.

/// The most values a dataset may declare: 2^27 doubles (1 GiB), far above any run's series.
constexpr hssize_t max_dataset_values = hssize_t(1) << 27;
/// The longest string an attribute or dataset may declare (a case file's text is a few kB).
constexpr std::size_t max_string_bytes = std::size_t(1) << 24;

/// @brief Whether @p parent holds a link @p name.
bool exists(hid_t parent, const char* name);
/// @brief Whether @p obj has an attribute @p name.
bool has_attr(hid_t obj, const char* name);
/// @brief Where @p obj is in the file ("/metadata"), for messages.
std::string name_of(hid_t obj);

/// @brief A string attribute; empty when absent.
std::string read_attr_string(hid_t obj, const char* name);
/// @brief A numeric attribute as a double; InputError when absent.
double read_attr_double(hid_t obj, const char* name);
/// @brief A numeric attribute as an integer; InputError when absent.
long long read_attr_int(hid_t obj, const char* name);
/// @brief A numeric attribute, nullopt when absent.
std::optional<double> read_attr_optional(hid_t obj, const char* name);
/// @brief A string dataset; empty when absent.
std::string read_dataset_string(hid_t parent, const char* name);
/// @brief A numeric dataset of any rank, flattened row-major; InputError when absent.
std::vector<double> read_doubles(hid_t parent, const char* name);
/// @brief The same, nullopt when absent.
std::optional<std::vector<double>> read_optional(hid_t parent, const char* name);
/// @brief Group @p name of @p file; InputError when it is missing or not a group.
Handle open_group(hid_t file, const char* name);

}  // namespace grainlift::hdf5
