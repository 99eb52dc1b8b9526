"""The Studio's Texture mode in a real headless Chromium (issue 22): the mode shows a
preset's image (checked from a screenshot, against the CPU kernel's pixels), a broken text
is marked at the line and column the graph loader names, and fixing it shows the new image."""

from __future__ import annotations

import io

import numpy as np
import pytest

from sylva.texture import graph as tg


@pytest.fixture(scope="module")
def page(browser, live):
    ctx = browser.new_context(viewport={"width": 1280, "height": 800}, bypass_csp=True,
                              device_scale_factor=1)
    pg = ctx.new_page()
    pg.errors = []
    pg.on("pageerror", lambda e: pg.errors.append(str(e)))
    # the bad text's 400 is expected; any other console error is not
    pg.on("console", lambda m: m.type == "error" and "status of 4" not in m.text
          and pg.errors.append(m.text))
    pg.goto(live.url + "/")
    pg.wait_for_selector("body[data-ready='1']", timeout=30_000)
    yield pg
    ctx.close()


def until(page, expression: str, timeout: float = 60_000) -> None:
    page.wait_for_function(expression, timeout=timeout, polling=100)


def shot(page) -> np.ndarray:
    from PIL import Image

    # the image's own pixels: its box may sit at a fraction of a pixel (the layout centres
    # it), which an element screenshot rounds outwards
    box = page.evaluate("""() => { const r = document.querySelector('#tex-image')
        .getBoundingClientRect(); return [r.x, r.y, r.width, r.height]; }""")
    x, y, w, h = (round(v) for v in box)
    data = page.screenshot(clip={"x": x, "y": y, "width": w, "height": h})
    return np.asarray(Image.open(io.BytesIO(data)).convert("RGB")).astype(float)


def test_texture_mode_shows_the_graphs_image_and_marks_a_bad_line(page, workspace):
    page.click("[data-mode-button=texture]")
    until(page, "window.studio.texture && window.studio.texture.shown >= 1 "
                "&& !window.studio.texture.busy")
    assert page.is_visible("#dock-texture") and page.is_hidden("#dock-editor")
    assert page.is_visible("#tex-image") and page.is_visible("#dock-tex-nodes")
    text = page.evaluate("window.studio.texture.editor.text")
    assert text == tg.from_recipe("arabescato-marble").dumps()
    # the preview of the 512 x 512 preset is 256 x 256, shown pixel for pixel: the pixels
    # on screen are the CPU kernel's (PNG, no scaling; colour management may move a level)
    want = tg.loads(text).image((256, 256)).astype(float)
    got = shot(page)
    assert got.shape == want.shape, got.shape
    assert want.std() > 10 and np.abs(got - want).mean() < 1.0
    assert "marble" in page.text_content("#tex-nodes")
    # another preset: a colour of a different kind replaces it
    page.select_option("#tex-preset", "seahorse-valley")
    until(page, "window.studio.texture.shown >= 2 && !window.studio.texture.busy "
                "&& window.studio.texture.editor.text.includes('mandelbrot')")
    fractal = shot(page)
    assert np.abs(fractal - want).mean() > 20
    # break the type of the output node: the marker sits on that line, the image stays
    broken = page.evaluate("""() => {
        const ed = window.studio.texture.editor;
        const t = ed.text.replace('type = "mandelbrot"', 'type = "mandelbrod"');
        ed.setText(t);
        return t;
    }""")
    line = broken.splitlines().index('type = "mandelbrod"') + 1
    until(page, "window.studio.texture.error !== null && !window.studio.texture.busy")
    err = page.evaluate("window.studio.texture.error")
    assert err["line"] == line and err["column"] == 8, err
    assert page.is_visible("#tex-error") and f":{line}:8:" in page.text_content("#tex-error")
    assert page.locator("#tex-editor .cm-error-line").count() == 1
    marked = page.evaluate("""() => {
        const el = document.querySelector('#tex-editor .cm-error-line');
        return el && el.textContent;
    }""")
    assert marked == 'type = "mandelbrod"'
    assert np.abs(shot(page) - fractal).mean() < 1.0  # the last good image is kept
    # fixing it clears the marker and renders again
    n = page.evaluate("window.studio.texture.shown")
    page.evaluate("""() => { const ed = window.studio.texture.editor;
        ed.setText(ed.text.replace('mandelbrod', 'mandelbrot')); }""")
    until(page, f"window.studio.texture.shown > {n} && !window.studio.texture.busy")
    assert page.is_hidden("#tex-error") and page.locator(
        "#tex-editor .cm-error-line").count() == 0
    # Save: the TOML as edited and its image at the graph's size, in the workspace
    page.fill("#tex-path", "browser/ship.toml")
    page.click("#tex-save")
    until(page, "document.querySelector('#st-message').textContent.startsWith('Saved')")
    saved = (workspace / "browser" / "ship.toml").read_text(encoding="utf-8")
    assert saved == page.evaluate("window.studio.texture.editor.text")
    from PIL import Image

    with Image.open(workspace / "browser" / "ship.png") as im:
        assert np.array_equal(np.asarray(im.convert("RGB")), tg.loads(saved).image())
    assert "browser/ship.toml" in page.inner_text("#tex-files")
    assert not page.errors, page.errors
