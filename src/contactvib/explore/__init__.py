"""``contactvib explore``: the contact oscillator live in the browser (Panel on Bokeh).

:mod:`.state` holds the operating point, its URL parameters and its checks (pure Python);
:mod:`.app` builds one page per browser session; :mod:`.server` serves it.
"""
