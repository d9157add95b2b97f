/***************************************************************************
  userguide.h - where the installed user guide is
  -------------------------------------------------------------------------
  The guide (docs/, as HTML by scripts/docs_html.py) is installed beside
  the provider library: <prefix>/share/geostation/docs next to
  <prefix>/lib/libgeostation_processing.so. In a build folder the pages
  are in <build>/docs-html, next to <build>/processing.
 ***************************************************************************/
#ifndef GEOSTATION_USERGUIDE_H
#define GEOSTATION_USERGUIDE_H

#include <QString>

#include "geostation_processing_export.h"

namespace GeoStationProcessing
{
  /**
   * A page of the user guide ("algorithms/extract_roads.html",
   * "getting-started.html") as a file URL, or an empty string when the
   * guide is not installed (built without python3-markdown).
   */
  GEOSTATION_PROCESSING_EXPORT QString userGuidePage( const QString &page );
} // namespace GeoStationProcessing

#endif // GEOSTATION_USERGUIDE_H
