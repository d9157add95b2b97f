/***************************************************************************
  geostationalgorithm.h - the base of GeoStation's Processing algorithms
  -------------------------------------------------------------------------
  QGIS catches only QgsProcessingException from an algorithm (in
  qgis_process, in the Processing dialog's background task and in models):
  any other exception ends QGIS. Core reports failures it cannot foresee
  (a corrupt DEM tile met in the middle of a batch, memory running out) as
  std::exception; this base turns them into one QgsProcessingException
  that names the algorithm and says what happened.

  Its choices (enums) are named by their option ("dark"), as the
  algorithms' help says, and also taken by their index (0), as QGIS takes
  any enum's: an index is turned into the option's name before the
  parameters are checked and run.
 ***************************************************************************/
#ifndef GEOSTATIONALGORITHM_H
#define GEOSTATIONALGORITHM_H

#include <qgsprocessingalgorithm.h>

#include "geostation_processing_export.h"
#include "outputsink.h"

namespace GeoStationProcessing
{

class GEOSTATION_PROCESSING_EXPORT GeoStationAlgorithm : public QgsProcessingAlgorithm
{
    friend class OutputSink; // QGIS's sentences for a sink that cannot be opened or written

  public:
    /**
     * The help as the dialog and qgis_process show it: helpText() with each
     * parameter and output named by its label (up to its first bracket),
     * its name in brackets: "Minimum contrast" (MIN_CONTRAST).
     */
    QString shortHelpString() const final;
    //! The algorithm's page of the installed user guide (userguide.h); empty where there is none (QGIS then hides the Help button).
    QString helpUrl() const override;

  protected:
    //! The algorithm's help, naming its parameters and outputs by their names (MIN_CONTRAST).
    virtual QString helpText() const = 0;

    //! The algorithm's work (what processAlgorithm() is for other algorithms).
    virtual QVariantMap processGeoStation( const QVariantMap &parameters, QgsProcessingContext &context, QgsProcessingFeedback *feedback ) = 0;

    /**
     * Runs processGeoStation(); a std::exception from it becomes a
     * QgsProcessingException with its message, std::bad_alloc one that
     * says memory ran out.
     */
    QVariantMap processAlgorithm( const QVariantMap &parameters, QgsProcessingContext &context, QgsProcessingFeedback *feedback ) final;

    //! Checks the parameters with each choice given by index taken by its name.
    bool checkParameterValues( const QVariantMap &parameters, QgsProcessingContext &context, QString *message = nullptr ) const override;

    //! The parameters with every choice (of an enum named by its options) given by index replaced by its option.
    QVariantMap withChoicesByName( const QVariantMap &parameters ) const;

    //! True if the caller asked for the optional output `name`: a destination given and not left empty.
    static bool outputRequested( const QVariantMap &parameters, const QString &name );

    //! The output `name` opened for writing (outputsink.h); one sentence when it cannot be.
    OutputSink openOutput( const QVariantMap &parameters, const QString &name, QgsProcessingContext &context, const QgsFields &fields,
                           QgsWkbTypes::Type type, const QgsCoordinateReferenceSystem &crs = QgsCoordinateReferenceSystem() ) const;
};

} // namespace GeoStationProcessing

#endif // GEOSTATIONALGORITHM_H
