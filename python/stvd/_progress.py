"""Progress reports of a propagation: a function of the caller, or a tqdm bar."""

import warnings


class _TqdmBar:
    """A tqdm bar over the domain's vertices, advanced by the library's reports."""

    def __init__(self, tqdm):
        self._tqdm = tqdm
        self._bar = None

    def __call__(self, finalized, total, front_distance):
        if self._bar is None:
            self._bar = self._tqdm(total=total, unit="vertex", unit_scale=True, desc="propagating")
        self._bar.update(finalized - self._bar.n)
        self._bar.set_postfix_str(f"front at {front_distance:.1f} mm", refresh=False)
        return True

    def finish(self, finalized):
        if self._bar is not None:
            self._bar.update(finalized - self._bar.n)

    def close(self):
        if self._bar is not None:
            self._bar.close()


class progress_reporter:
    """The callback handed to the library for ``progress=``, as a context.

    ``None`` or ``False``: none. ``True``: a tqdm bar when tqdm can be
    imported (a warning otherwise). A callable: called as
    ``f(finalized_vertices, domain_vertices, front_distance_mm)`` at the start,
    at least every 0.05 s and at the end; returning ``False`` cancels the run.
    """

    def __init__(self, progress):
        self._bar = None
        self.callback = None
        if progress is True:
            try:
                from tqdm.auto import tqdm
            except ImportError:
                warnings.warn("progress=True: tqdm is not installed (Debian: python3-tqdm); no progress bar",
                              stacklevel=3)
            else:
                self._bar = _TqdmBar(tqdm)
                self.callback = self._bar
        elif callable(progress):
            self.callback = progress
        elif progress is not None and progress is not False:
            raise TypeError(f"progress: expected None, a bool or a callable, got {type(progress).__name__}")

    def __enter__(self):
        return self

    def finish(self, finalized):
        """Moves a bar to the final count of finalised vertices (the library
        reports at intervals in time)."""
        if self._bar is not None:
            self._bar.finish(finalized)

    def __exit__(self, *exc):
        if self._bar is not None:
            self._bar.close()
        return False
