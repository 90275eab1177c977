#!/usr/bin/env python3
"""Walks every registered model, and every measured file the service lists (/api/data), through
the viewer in one chromium-headless-shell session (tests/viewer_test.sh): for each, model A's spec
field is set to the model's example spec (`ganzfeld models`: every parameter at its default) and
the page rebuilds its row; window.panelReport() then says what each panel holds. A panel is empty
when the lobe has no f > 0, the polar plot no sample > 0, or a sphere view no lit pixel on the
sphere; a row with an error is empty too. Writes one JSON line per model and a summary on stdout;
exits 1 when any panel is empty.

Usage: viewer_walk.py BROWSER URL   (URL: the page, with its small-size parameters)
"""
import json
import sys
import time
import urllib.request

from viewer_drive import Browser, profile_directory

TIMEOUT_SECONDS = 300  # one model's row on a loaded 2-core machine: a few tables or cubature spheres


def specs(base):
    """Every registered model's example spec, but for those needing a data file: the listed files."""
    models = json.load(urllib.request.urlopen(base + '/api/models'))['models']
    data = json.load(urllib.request.urlopen(base + '/api/data'))
    out = [(m['name'], m['example']) for m in models if 'file=DATA' not in m['example']]
    out += [(f['model'] + ' (data: ' + f['name'] + ')', f['spec']) for f in data['files']]
    measured = [m['name'] for m in models if 'file=DATA' in m['example']]
    return out, measured, data['files']


def main():
    browser_path, url = sys.argv[1], sys.argv[2]
    base = url.split('/?')[0]
    walk, measured, files = specs(base)
    missing = [m for m in measured if m not in {f['model'] for f in files}]
    empty, rows = [], []
    with profile_directory() as profile:
        browser = Browser(browser_path, profile)
        try:
            browser.open(url, TIMEOUT_SECONDS)
            for name, spec in walk:
                started = time.monotonic()
                builds = browser.evaluate('state.builds')
                browser.evaluate('(() => { const f = document.getElementById("spec-a"); f.value = %s;'
                                 ' f.dispatchEvent(new Event("change")); })()' % json.dumps(spec))
                browser.wait_for(f'state.builds > {builds}', f'the row of {spec}', TIMEOUT_SECONDS)
                for _ in range(TIMEOUT_SECONDS // 60):  # imagesArrived gives up after 60 s; cubature spheres take longer
                    if browser.evaluate('window.imagesArrived()'):
                        break
                report = browser.evaluate('JSON.stringify(window.panelReport(16))')
                report = json.loads(report) if report else []
                row = report[0] if report else {'error': browser.evaluate(
                    'document.querySelector("#panels .error")?.textContent || "no row"')}
                panels = {'lobe': bool(row.get('lobe', {}).get('max', 0) > 0), 'polar': row.get('polar', 0) > 0}
                for view in row.get('views', []):
                    panels[view['view']] = view['lit'] > 0
                full = not row.get('error') and len(panels) == 5 and all(panels.values())
                rows.append({'model': name, 'spec': spec, 'panels': panels, 'error': row.get('error', ''),
                             'sources': [v['source'] for v in row.get('views', [])],
                             'seconds': round(time.monotonic() - started, 1)})
                print(json.dumps(rows[-1]), flush=True)
                if not full:
                    empty.append(name)
        finally:
            browser.close()
    print(json.dumps({'models': len(walk), 'registered': len(walk) - len(files) + len(measured),
                      'data_files': len(files), 'measured_without_a_file': missing, 'empty': empty}))
    sys.exit(1 if empty or missing else 0)


if __name__ == '__main__':
    main()
