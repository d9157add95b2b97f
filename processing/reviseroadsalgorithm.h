/***************************************************************************
  reviseroadsalgorithm.h - geostation:revise_roads
  -------------------------------------------------------------------------
  An old road map held against a new stereo pair (core/revision): each
  map road confirmed, moved, not found or outside, split where that
  changes, and the roads the pair shows that the map does not.
 ***************************************************************************/
#ifndef REVISEROADSALGORITHM_H
#define REVISEROADSALGORITHM_H

#include "geostationalgorithm.h"

#include "geostation_processing_export.h"

namespace GeoStationProcessing
{

class GEOSTATION_PROCESSING_EXPORT ReviseRoadsAlgorithm : public GeoStationAlgorithm
{
  public:
    QString name() const override;
    QString displayName() const override;
    QStringList tags() const override;
    QString group() const override;
    QString groupId() const override;
    QString helpText() const override;
    ReviseRoadsAlgorithm *createInstance() const override;

  protected:
    void initAlgorithm( const QVariantMap &configuration = QVariantMap() ) override;
    QVariantMap processGeoStation( const QVariantMap &parameters, QgsProcessingContext &context, QgsProcessingFeedback *feedback ) override;
};

} // namespace GeoStationProcessing

#endif // REVISEROADSALGORITHM_H
