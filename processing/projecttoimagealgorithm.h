/***************************************************************************
  projecttoimagealgorithm.h - geostation:project_to_image
  -------------------------------------------------------------------------
  Map features with heights -> the pixels where they appear in one oriented
  image, as an image-space layer (x = col, y = -row, no CRS) that overlays the
  raw image in QGIS (docs/conventions.md §1, §8).
 ***************************************************************************/
#ifndef PROJECTTOIMAGEALGORITHM_H
#define PROJECTTOIMAGEALGORITHM_H

#include "geostationalgorithm.h"

#include "geostation_processing_export.h"

namespace GeoStationProcessing
{

class GEOSTATION_PROCESSING_EXPORT ProjectToImageAlgorithm : public GeoStationAlgorithm
{
  public:
    QString name() const override;
    QString displayName() const override;
    QStringList tags() const override;
    QString group() const override;
    QString groupId() const override;
    QString helpText() const override;
    ProjectToImageAlgorithm *createInstance() const override;

  protected:
    void initAlgorithm( const QVariantMap &configuration = QVariantMap() ) override;
    QVariantMap processGeoStation( const QVariantMap &parameters, QgsProcessingContext &context, QgsProcessingFeedback *feedback ) override;
};

} // namespace GeoStationProcessing

#endif // PROJECTTOIMAGEALGORITHM_H
