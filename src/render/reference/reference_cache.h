#pragma once
// On-disk cache of finished references: <dir>/<key>.mean.pfm, .stderr.pfm
// and .json. The key hashes everything that changes the image: the scene's
// geometry, materials, textures and lights after settings overrides, sun,
// sky, camera matrices, resolution and the reference settings.
#include "gl/image_io.h"
#include "render/reference/reference_passes.h"
#include "render/view.h"

#include <nlohmann/json.hpp>

#include <optional>
#include <string>

namespace rtgi {

std::string referenceCacheKey(const Scene& scene, const Settings& settings, const ReferenceConstants& c,
                              const View& view);

struct CachedReference {
    FloatImage mean, standardError;
    nlohmann::json info;
};

// Both return / do nothing when settings.reference.cacheDir is "off".
std::optional<CachedReference> loadCachedReference(const std::string& dir, const std::string& key);
void storeCachedReference(const std::string& dir, const std::string& key, const CachedReference& ref);

// The reference's settings as recorded in the cache and in results.json.
nlohmann::json referenceSettingsJson(const ReferenceConstants& c);

}  // namespace rtgi
