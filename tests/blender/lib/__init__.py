"""What the Blender tests share, one module per concern. Blender runs each
test as `blender [-b] -P tests/blender/NAME.py -- ARGS`, so a script puts
its own folder on sys.path first and imports from here:

    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
    from lib.checks import check, run_checks  # noqa: E402

  checks    check() and the failures it counts; run_checks() turns them
            into Blender's exit status (headless scripts)
  headless  the headless scripts' arguments (CLOTHBAKE_EXE SOURCE_DIR
            WORK_DIR after Blender's "--"), the test scenes, enable_addon()
  program   run(): the clothbake program under test, its failure raised
  images    an image's pixels, relative RMSE, a still render, a PNG sheet
  noise     blocks(), Noisy (a render and its two-render noise) and
            within_noise(): the bound every material comparison uses
  errors    an operator's ERROR report: expect_report() (exact text) and
            expect_error() (every text contained)
  scene     select()
  window    the window driver of the tests in Blender's real window
            (drive(): steps from a timer, the window drawn between them)
            and area()
"""
