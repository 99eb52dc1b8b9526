

def test_each_thread_renders_with_its_own_context():
    import threading

    from sylva.render import get_context

    main_ctx = get_context()
    seen = {}

    def work():
        seen["ctx"] = get_context()
        seen["again"] = get_context()

    t = threading.Thread(target=work)
    t.start()
    t.join()
    assert seen["ctx"] is seen["again"] and seen["ctx"] is not main_ctx
    assert get_context() is main_ctx
