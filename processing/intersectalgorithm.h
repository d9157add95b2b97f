/***************************************************************************
  intersectalgorithm.h - geostation:intersect
  -------------------------------------------------------------------------
  Multi-ray space intersection of measured image points (docs/conventions.md §8).
 ***************************************************************************/
#ifndef INTERSECTALGORITHM_H
#define INTERSECTALGORITHM_H

#include "geostationalgorithm.h"

#include "geostation_processing_export.h"

namespace GeoStationProcessing
{

class GEOSTATION_PROCESSING_EXPORT IntersectAlgorithm : public GeoStationAlgorithm
{
  public:
    QString name() const override;
    QString displayName() const override;
    QStringList tags() const override;
    QString group() const override;
    QString groupId() const override;
    QString helpText() const override;
    IntersectAlgorithm *createInstance() const override;

  protected:
    void initAlgorithm( const QVariantMap &configuration = QVariantMap() ) override;
    QVariantMap processGeoStation( const QVariantMap &parameters, QgsProcessingContext &context, QgsProcessingFeedback *feedback ) override;
};

} // namespace GeoStationProcessing

#endif // INTERSECTALGORITHM_H
