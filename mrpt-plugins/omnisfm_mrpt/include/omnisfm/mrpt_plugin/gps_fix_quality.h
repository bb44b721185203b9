#pragma once
// How a GPS receiver's NMEA sentences state its accuracy, and back: the fix quality of GGA
// (1 autonomous, 2 differential, 4 RTK fixed, 5 RTK float) implies a user-equivalent range error
// (UERE, the error of one satellite's range), and the dilutions of precision (GGA's HDOP, GSA's
// VDOP) scale it to the position's:
//   horizontal sigma per axis = HDOP * UERE / sqrt(2)     (HDOP bounds the 2D RMS error)
//   vertical sigma            = VDOP * UERE
// The simulator writes its noise this way and the rawlog reader recovers it exactly.

namespace omnisfm::mrpt_plugin {

struct GpsFixQuality {
  int fix_quality = 1;  // GGA's field
  int satellites = 12;
  double hdop = 1, vdop = 1.5;
};

// The UERE, in metres, of a GGA fix quality; 0 for an invalid fix (0) or one without a
// measurement (6 dead reckoning, 7 manual, 8 simulation mode are taken as autonomous).
double user_equivalent_range_error(int fix_quality);

// The fix a receiver with this noise reports: the best quality whose UERE the noise does not
// beat by more than a factor 2, with the dilutions that make up the rest. Noise of 0 reads as
// RTK fixed at the smallest dilution a receiver reports (0.5).
GpsFixQuality gps_fix_quality_of(double horizontal_sigma, double vertical_sigma);

struct GpsSigma {
  double horizontal = 0, vertical = 0;
};
// The noise a fix states. Without a VDOP (no GSA sentence), the vertical sigma is taken as twice
// the horizontal, as for a typical satellite geometry.
GpsSigma gps_sigma_of(int fix_quality, double hdop, double vdop_or_zero);

}  // namespace omnisfm::mrpt_plugin
