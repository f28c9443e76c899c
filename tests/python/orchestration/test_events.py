"""The event stream: subscribers by type; a failing subscriber never stops the publisher."""

from grasp_pipeline.orchestration.events import EventBus, PlanEvent, StageEvent, Tick


def test_subscribers_receive_only_their_event_type():
    bus, got = EventBus(), []
    bus.subscribe(StageEvent, got.append)
    bus.publish(Tick(0.1))
    bus.publish(StageEvent(0.2, "scan"))
    assert [e.name for e in got] == ["scan"]
    assert bus.wants(StageEvent) and not bus.wants(PlanEvent)


def test_a_failing_subscriber_is_dropped_and_reported_and_others_still_run():
    bus, got = EventBus(), []

    def broken(ev):
        raise OSError("disk full")

    bus.subscribe(Tick, broken)
    bus.subscribe(Tick, got.append)
    bus.publish(Tick(0.0))
    bus.publish(Tick(0.1))
    assert len(got) == 2
    assert len(bus.failures) == 1 and "disk full" in bus.failures[0]


def test_subscribing_or_unsubscribing_while_publishing_takes_effect_from_the_next_event():
    bus, got = EventBus(), []

    def once(ev):  # leaves after its first event and brings in another listener
        got.append(("once", ev.time_s))
        bus.unsubscribe(Tick, once)
        bus.subscribe(Tick, lambda e: got.append(("late", e.time_s)))

    bus.subscribe(Tick, once)
    bus.subscribe(Tick, lambda e: got.append(("always", e.time_s)))
    bus.publish(Tick(0.0))
    bus.publish(Tick(0.1))
    assert got == [("once", 0.0), ("always", 0.0), ("always", 0.1), ("late", 0.1)]
    bus.unsubscribe(Tick, once)  # no longer subscribed: nothing happens
    assert bus.wants(Tick)
