/***************************************************************************
  htmlreport.h - the report a person reads, as one HTML file
  -------------------------------------------------------------------------
  The algorithms that adjust or measure write their figures twice: a JSON
  REPORT for machines and, on request, an HTML report (REPORT_HTML) that
  QGIS shows in its Results Viewer: a summary, tables, residual vectors
  drawn over the image frame and histograms, as inline SVG so that the
  file stands alone (no scripts, no images beside it, nothing fetched).
  Every text is escaped; a number that is not finite is shown as "-".
 ***************************************************************************/
#ifndef HTMLREPORT_H
#define HTMLREPORT_H

#include <QPair>
#include <QPointF>
#include <QPolygonF>
#include <QSizeF>
#include <QString>
#include <QStringList>
#include <QVector>

namespace GeoStationProcessing
{
  //! A residual drawn as an arrow from where it was measured.
  struct ResidualArrow
  {
    QPointF at;       //!< image pixel (col, row) or frame coordinates
    QPointF residual; //!< in the units of the plot's residuals (drawn magnified)
    QString label;    //!< shown when the pointer rests on the arrow
    bool flagged = false; //!< a blunder or a point left out: drawn in red
  };

  class HtmlReport
  {
    public:
      explicit HtmlReport( const QString &title );

      void heading( const QString &text );
      void paragraph( const QString &text );
      //! A two-column table: what, value.
      void keyValues( const QVector<QPair<QString, QString>> &rows );
      //! A table; cells are text (numbers formatted by the caller, e.g. with number()).
      void table( const QStringList &headers, const QVector<QStringList> &rows );

      /**
       * The arrows over a frame of `frame` (width, height; y down, as image
       * rows): each from its point to the point plus its residual magnified
       * by a round factor chosen so that the longest arrow is about a tenth
       * of the frame, with the factor and a scale bar in `unit` beneath.
       */
      void residualPlot( const QString &caption, const QSizeF &frame, const QVector<ResidualArrow> &arrows, const QString &unit );

      //! Polylines over a frame of `frame` (y down, as image rows), as the lines found in an image.
      void linesPlot( const QString &caption, const QSizeF &frame, const QVector<QPolygonF> &lines );

      //! A histogram of `values` (non-finite ones left out) in `unit`, about sqrt(n) bins (5 to 30).
      void histogram( const QString &caption, const QVector<double> &values, const QString &unit );

      //! The whole page, UTF-8.
      QByteArray toUtf8() const;

    private:
      QString mTitle;
      QString mBody;
      int mPlots = 0; //!< each plot's arrow heads named apart
  };

  //! `value` with `decimals` decimals; "-" when it is not finite.
  QString number( double value, int decimals );

  //! 1, 2 or 5 times a power of ten, the nearest below or at `value` (> 0).
  double roundDown125( double value );

} // namespace GeoStationProcessing

#endif // HTMLREPORT_H
