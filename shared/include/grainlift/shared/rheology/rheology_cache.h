// The calibrated rheology of a grain material, cached like the prepared beds: `grainlift
// calibrate` saves its rheology file under a name made from everything the shear cell's result
// depends on (grain sizes, density, contact law and its parameters, friction, time step, the
// cell's pressure), and a run whose case does not state a mu(I) law of its own finds it there.
//
//   $XDG_CACHE_HOME/grainlift/rheology/rheology-<key>.toml   (dem.packing_cache = "auto")
//   <dem.packing_cache>/rheology/rheology-<key>.toml         (a folder of the user's)
//   nothing                                                   (dem.packing_cache = "")
// An entry is the rheology file with a last line "# grainlift cache 2 fnv1a64 <16 hex>", the
// cache format and a checksum of every byte above it: a damaged entry is found, reported as a
// cache problem and removed (an entry written before checksums, without that line, is read
// as it is).
#pragma once

#include <string>

#include "grainlift/shared/case/case_model.h"
#include "grainlift/shared/rheology/rheology_file.h"

namespace grainlift {

/// @brief The cache folder of one kind of cached object ("packings", "rheology") for the
/// dem.packing_cache setting: "auto" = $XDG_CACHE_HOME/grainlift/<kind> (or
/// ~/.cache/grainlift/<kind>), "" = no cache (returns ""), a folder = that folder for "packings"
/// and <folder>/<kind> for other kinds.
std::string cache_folder(const std::string& setting, const std::string& kind);

/// @brief 16 hex digits naming the material of @p c as the shear cell sees it, at confining
/// pressure @p pressure (Pa): grains.diameter, polydispersity, density, friction, the contact
/// law's name and every contact parameter, dem.dt and the pressure (6 significant digits).
std::string grain_material_key(const Case& c, double pressure);

/// @brief Path of the cached rheology file of @p c's grains at @p pressure ("" when the case
/// switches caching off).
std::string rheology_cache_path(const Case& c, double pressure);

/// @brief The dilatancy law Phi(I) of @p law and the top of its calibrated range into @p cn
/// (continuum.dilatancy reads them). Inline: the case reader calls it without the cache.
inline void take_phi_i(const RheologyFile& law, ContinuumSection& cn) {
  cn.phi_max = law.phi_i.phi_max;
  cn.phi_a = law.phi_i.a;
  cn.phi_I_max = law.I_max;
}

/// @brief Writes @p law to the cache entry @p path (made by rheology_cache_path) with its
/// checksum line, atomically. @throws RunError when it cannot be written.
void cache_rheology(const std::string& path, const RheologyFile& law);

/// @brief When @p c's continuum has no law of its own (law_source "default") and the cache holds
/// a rheology file for its grains at c.continuum_pressure(), takes mu_s, mu_2, I0 from it and
/// sets law_source "calibration cache" and rheology_file to the cached file.
/// @return a one-line note for the user saying which law the continuum will use and why (empty
/// when the case states its law, or has no confining pressure: the continuum refuses it).
/// A damaged entry (checksum, format or contents) is removed and the note says so: the case
/// then runs as if nothing were cached.
std::string use_cached_rheology(Case& c);

}  // namespace grainlift
