"""Serve the explore page (Bokeh server through Panel) on 127.0.0.1 unless ``host`` is given."""

from __future__ import annotations

from contactvib.explore.level_graph import GRAPH_TIME_LIMIT_S
from contactvib.explore.state import TIME_LIMIT_S


def serve(ops, port: int = 0, host: str = "127.0.0.1", open_browser: bool = True,
          limit_s: float = TIME_LIMIT_S, ready=None, levels=None, graph_limit_s: float = GRAPH_TIME_LIMIT_S,
          start=None, warm=None, page=None):
    """Serve until stopped; ``ops = (check, find, continue, level inputs)`` (:func:`.app._compute`,
    :class:`.app.Page`). ``ready(url)`` is called once the server listens (the CLI prints it).
    ``levels``: a :class:`.dataset_view.DatasetLevels` whose resonance graphs the pages show
    (read-only, shared by the sessions); without it a page computes the graph of its level in
    the background, stopped after ``graph_limit_s``. ``start``: the first point of every page
    (a :class:`.state.Point`, its law and law file; default the paper's). ``warm()`` is called
    once the port is bound (a taken port fails first) and before any page is answered or
    ``ready`` is called: the CLI compiles the first search's kernels there. ``page``: a callable
    that builds another page for each session instead (a system's:
    :func:`.system_page.build_system_page`), ``ops`` then unused."""
    import panel as pn

    from contactvib.explore.app import build

    def session_page():
        return build(ops, limit_s, levels, graph_limit_s, start) if page is None else page()

    if not port:
        import socket

        with socket.socket() as s:
            s.bind((host, 0))
            port = s.getsockname()[1]
    origins = sorted({f"{host}:{port}", f"127.0.0.1:{port}", f"localhost:{port}"})
    server = pn.serve({"/": session_page}, port=port, address=host, show=False,
                      start=False, title="contactvib explore", websocket_origin=origins)
    server.start()
    if warm is not None:
        warm()
    url = f"http://{host}:{server.port}/"
    if ready is not None:
        ready(url)
    if open_browser:
        import webbrowser

        server.io_loop.add_callback(webbrowser.open, url)
    server.io_loop.start()
