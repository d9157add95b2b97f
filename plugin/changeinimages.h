/***************************************************************************
  changeinimages.h - a reviewed map change shown in the Multiview
  -------------------------------------------------------------------------
  A map revision's change has two courses: the map's (old) and the one the
  images show (new). To show them in the Multiview, both are carried into
  the block CRS and into each view's image; where the views' images do not
  see the change, the block's images that do are chosen, the one that sees
  it nearest its centre first.
 ***************************************************************************/
#ifndef GEOSTATIONCHANGEINIMAGES_H
#define GEOSTATIONCHANGEINIMAGES_H

#include <functional>
#include <optional>
#include <vector>

#include <Eigen/Core>

#include <QStringList>

#include <qgscoordinatereferencesystem.h>
#include <qgsgeometry.h>

#include "geometry/projection.h"

/**
 * A line's vertices in the block CRS (all parts, in order). A vertex without
 * a height takes `heightWhereNone`; a geometry that cannot be transformed
 * gives none.
 */
std::vector<Eigen::Vector3d> courseInBlockCrs( const QgsGeometry &course, const QgsCoordinateReferenceSystem &courseCrs,
    const QgsCoordinateReferenceSystem &blockCrs, double heightWhereNone );

//! The mean height of a course (nullopt for none or no finite height).
std::optional<double> meanHeight( const std::vector<Eigen::Vector3d> &course );

/**
 * The images (of `imageIds`, oriented ones only, through `oriented`) whose
 * frame holds `point`, the one where it lies nearest the image centre first.
 */
QStringList imagesSeeing( const Eigen::Vector3d &point, const QStringList &imageIds,
                          const std::function<const geostation::OrientedImage *( const QString & )> &oriented );

#endif // GEOSTATIONCHANGEINIMAGES_H
