"""numba kernels, grouped by job; each module ends with the Python wrappers the rest of sesp calls.

* :mod:`.overlap`: segment-pair tests, the Minkowski raster and the direct engine;
* :mod:`.hull`: each curve against the other's filled convex hull (entanglement);
* :mod:`.orientations`: blocked φ intervals at a fixed translation, exact in φ;
* :mod:`.depth`: lower bounds on the depth of excluded positions, exact in φ;
* :mod:`.spectra`: sums over Fourier spectra (the third virial coefficient);
* :mod:`.cells`: quadtree leaves' adjacency and their components (the one union-find);
* :mod:`.common`: the shared jit options and helpers.

Kernels take and return arrays and scalars only, and write into outputs
their wrapper allocated. Parallel kernels run ``prange`` over φ (or over
positions); each slice is written by one thread, so results do not depend
on the thread count.
"""
