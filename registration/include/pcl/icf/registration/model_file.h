/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#pragma once

/** \file
 * \brief Prepared models on disk: what IcfModel::build computes slowly (the closest-point
 * field, the point pair table) written once and read back in milliseconds, and a cache folder
 * that does it by itself.
 *
 * A file holds a format version, the preparation's key (preparationKey: the mesh's content,
 * the units and every parameter the preparation depends on), the mesh itself, a CRC-32 of all
 * that, the field and the table, and a CRC-32 of the whole: it stands alone, a model without
 * its mesh file.
 * Reading checks each: a truncated, corrupt, foreign-version or mismatched file throws
 * ModelFileError, never gives a model. The faces, the exact index and the surface samples are
 * rebuilt from the mesh on reading (they take milliseconds). */

#include <pcl/PolygonMesh.h>
#include <pcl/icf/registration/icf_model.h>

#include <stdexcept>
#include <string>

namespace pcl {
namespace icf {

/** \brief A prepared-model file that cannot be used: unreadable, truncated, corrupt, of
 * another format version, or prepared from another mesh or other parameters. */
class ModelFileError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/** The format version a file is written in; a file of another is refused. */
constexpr unsigned kModelFileVersion = 2;

/** \brief 16 hex digits that change with anything the preparation of \a mesh under \a params
 * depends on: the mesh's vertices, faces and field layout, the units (params.mesh.scale), the
 * tolerances, the field's and the point pair table's parameters, the seeds, and the format
 * version. Not the thread count (the preparation does not depend on it). */
std::string preparationKey(const pcl::PolygonMesh& mesh, const IcfModelParams& params);

/** \brief Writes \a model, prepared from \a mesh whose preparationKey is \a key, to \a path
 * with the mesh, atomically: into a temporary file beside it, then renamed, so a concurrent reader
 * sees the old file or the new one, never half of one. \throws ModelFileError when it cannot be
 * written. */
void writeModelFile(const IcfModel& model, const pcl::PolygonMesh& mesh, const std::string& key,
                    const std::string& path);

/** \brief The model of \a mesh under \a params read from \a path, which must have been written
 * for them (its key is preparationKey(mesh, params)). The same model IcfModel::build gives.
 * \throws ModelFileError (see the file's comment), InvalidMeshError for a mesh that cannot be
 * a model. */
IcfModel::ConstPtr readModelFile(const std::string& path, const pcl::PolygonMesh& mesh,
                                 const IcfModelParams& params);

/** \brief Whether \a path begins as a prepared-model file does (its magic bytes); says nothing
 * of whether the rest is sound. */
bool isModelFile(const std::string& path);

/** \brief The mesh a prepared-model file was prepared from, in its own units: what to give
 * readModelFile with the parameters the model is wanted under. Reads the file only up to the
 * mesh. \throws ModelFileError for a file that cannot be read or whose beginning is not sound
 * (magic, version, the checksum after the mesh). */
pcl::PolygonMesh readModelFileMesh(const std::string& path);

/** \brief The cache folder by default: $XDG_CACHE_HOME/pcl_icf, else $HOME/.cache/pcl_icf, else
 * "" (no cache). */
std::string defaultModelCacheFolder();

/** \brief A model from the cache, or built and added to it. */
struct CachedModel {
  IcfModel::ConstPtr model;
  bool from_cache = false;  ///< read from the cache (else built)
  std::string path;         ///< the cache entry ("" without a folder)
  /** Why the entry was not used or not written (a corrupt entry rebuilt, a folder that cannot
   * be written): "" when all went well. The model is right either way. */
  std::string warning;
};

/** \brief IcfModel::build(mesh, params) through the cache \a folder: the entry named by the
 * preparation's key is read when it is there and sound; otherwise the model is built and the
 * entry (re)written atomically. An unusable entry is rebuilt with a warning, never trusted.
 * \a folder "": no cache, the model is built. \throws what IcfModel::build throws. */
CachedModel buildModelCached(const pcl::PolygonMesh& mesh, const IcfModelParams& params,
                             const std::string& folder);

}  // namespace icf
}  // namespace pcl
