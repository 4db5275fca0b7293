"""The certified count's steps (:mod:`sesp.certified` defines the count; these compute it).

* :mod:`.settings` — the cost settings, none part of the definition;
* :mod:`.problem` — one count's fixed inputs, and what its rounds have tried;
* :mod:`.leaves` — the quadtree of cells and what is known at each centre;
* :mod:`.centres` — deciding a point: allowed (with its clearance), certified deep, or excluded;
* :mod:`.bounds` — upper bounds on the depth from the allowed points, the cells' statuses, new allowed points;
* :mod:`.depth` — certified lower and upper bounds on each candidate's depth;
* :mod:`.refine` — which cells could change the bracket, and their splitting;
* :mod:`.pipeline` — the rounds, and the result as arrays.

Each step is a function of explicit inputs that returns new arrays; the only state carried between rounds is
the allowed points found and :class:`.problem.Memo`, passed in the open.
"""
