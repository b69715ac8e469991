"""modalinfo: information-theoretic analysis of wavefront modal bases.

Subpackages
-----------
bases
    Pupil grids, Zernike polynomials, turbulence covariance, Karhunen-Loeve bases.
telemetry
    ``ModalLog`` and synthetic telemetry.
io
    Readers and writers for archived WFS logs (NPZ, CSV, FITS, HDF5).
information
    Mutual-information and entropy estimators.
ordering
    MI orderings of modal bases and fitting-error curves.
forecast
    Predictors of modal-coefficient time series and their evaluation.
"""

__version__ = "0.1.0"

__all__ = ["__version__"]
