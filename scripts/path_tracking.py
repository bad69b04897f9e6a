"""Cross-track error of a head path against a reference polyline (shared by the plot script
and the path-following rostests). Distances are to the nearest point of the whole polyline."""
import math


def distance_to_polyline(point, polyline):
    """Shortest distance [m] from (x, y) to a polyline given as a list of (x, y)."""
    px, py = point
    best = math.inf
    for (ax, ay), (bx, by) in zip(polyline[:-1], polyline[1:]):
        dx, dy = bx - ax, by - ay
        length_sq = dx * dx + dy * dy
        t = 0.0 if length_sq == 0.0 else max(0.0, min(1.0, ((px - ax) * dx + (py - ay) * dy) / length_sq))
        cx, cy = ax + t * dx, ay + t * dy
        best = min(best, math.hypot(px - cx, py - cy))
    return best


def tracking_errors(points, polyline):
    """Max and RMS distance [m] of the points to the polyline; (nan, nan) without points."""
    if not points or len(polyline) < 2:
        return math.nan, math.nan
    d = [distance_to_polyline(p, polyline) for p in points]
    return max(d), math.sqrt(sum(x * x for x in d) / len(d))
