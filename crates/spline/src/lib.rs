//! Cubic splines through via-points and the cost criteria of the method (filled by the spline issue).
