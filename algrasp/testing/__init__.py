"""Generators of test and benchmark parts (not part of the core: nothing in
``algrasp.geometry`` or ``algrasp.planning`` uses them). :mod:`algrasp.testing.shapes`
writes part documents — pies, rectangles, regular and random polygons, Bezier blobs — for
the tests, the benchmarks and property-based laws."""
