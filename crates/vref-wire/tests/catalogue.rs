//! The service catalogue that `vref wire-layout` prints is what the
//! `open_*` functions create: every service is opened for real (own root
//! path and prefix) and iceoryx2's record of it compared with the
//! catalogue's settings and types.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use iceoryx2::prelude::*;
use iceoryx2::service::static_config::message_type_details::{TypeDetail, TypeVariant};
use vref_scene::Side;
use vref_wire::ipc::{
    IpcSettings, Pattern, ServiceSpec, TypeRef, catalogue, create_node, open_answer_event,
    open_decision, open_gesture, open_reference, open_request_event, open_snapshot, open_stats,
};

fn isolated() -> (tempfile::TempDir, IpcSettings) {
    let dir = tempfile::tempdir().unwrap();
    let settings = IpcSettings {
        namespace: "cat".to_owned(),
        root_path: Some(dir.path().to_owned()),
        prefix: format!("vref_cat_{}_", std::process::id()),
        // Not the defaults, so that a setting that ignores them shows.
        max_clients: 5,
        max_subscribers: 3,
        initial_objects: 7,
        ..IpcSettings::default()
    };
    (dir, settings)
}

fn assert_type(what: &str, found: &TypeDetail, expected: &TypeRef) {
    let variant = match found.variant() {
        TypeVariant::FixedSize => "fixed_size",
        TypeVariant::Dynamic => "dynamic",
    };
    assert_eq!(
        (
            found.type_name().to_string(),
            variant,
            found.size(),
            found.alignment()
        ),
        (
            expected.type_name.to_owned(),
            expected.variant,
            expected.size,
            expected.align
        ),
        "{what}"
    );
}

fn spec<'a>(all: &'a [ServiceSpec], role: &str) -> &'a ServiceSpec {
    all.iter()
        .find(|s| s.role == role)
        .unwrap_or_else(|| panic!("no service {role}"))
}

fn check_pubsub(
    all: &[ServiceSpec],
    role: &str,
    name: &str,
    config: &iceoryx2::service::static_config::publish_subscribe::StaticConfig,
) {
    let s = spec(all, role);
    assert_eq!(s.name, name, "{role}");
    let Pattern::PublishSubscribe {
        payload,
        user_header,
        qos,
        ..
    } = &s.pattern
    else {
        panic!("{role} is not publish-subscribe");
    };
    assert_eq!(config.history_size(), qos.history_size, "{role}");
    assert_eq!(
        config.subscriber_max_buffer_size(),
        qos.subscriber_max_buffer_size,
        "{role}"
    );
    if let Some(n) = qos.subscriber_max_borrowed_samples {
        assert_eq!(config.subscriber_max_borrowed_samples(), n, "{role}");
    }
    assert_eq!(
        config.has_safe_overflow(),
        qos.enable_safe_overflow,
        "{role}"
    );
    assert_eq!(config.max_publishers(), qos.max_publishers, "{role}");
    assert_eq!(config.max_subscribers(), qos.max_subscribers, "{role}");
    let details = config.message_type_details();
    assert_type(role, &details.payload, payload);
    match user_header {
        Some(h) => assert_type(role, &details.user_header, h),
        None => assert_eq!(details.user_header.size(), 0, "{role}"),
    }
}

fn check_event(
    all: &[ServiceSpec],
    role: &str,
    name: &str,
    config: &iceoryx2::service::static_config::event::StaticConfig,
) {
    let s = spec(all, role);
    assert_eq!(s.name, name, "{role}");
    let Pattern::Event { qos, .. } = &s.pattern else {
        panic!("{role} is not an event");
    };
    assert_eq!(config.max_notifiers(), qos.max_notifiers, "{role}");
    assert_eq!(config.max_listeners(), qos.max_listeners, "{role}");
    assert_eq!(
        config.notifier_dead_event().map(|e| e.as_value()),
        Some(qos.notifier_dead_event),
        "{role}"
    );
}

#[test]
fn every_service_is_created_as_the_catalogue_says() {
    let (_dir, settings) = isolated();
    let node = create_node(&settings, "catalogue").unwrap();
    let all = catalogue(&settings);

    let mut checked = 0;
    for (side, role) in [(Side::Robot, "robot"), (Side::Human, "human")] {
        let (data, event) = open_snapshot(&node, &settings, side).unwrap();
        let data_role = format!("{role}_snapshot");
        check_pubsub(&all, &data_role, data.name().as_str(), data.static_config());
        check_event(
            &all,
            &format!("{data_role}_event"),
            event.name().as_str(),
            event.static_config(),
        );
        checked += 2;
    }
    let (data, event) = open_gesture(&node, &settings).unwrap();
    check_pubsub(&all, "gesture", data.name().as_str(), data.static_config());
    check_event(
        &all,
        "gesture_event",
        event.name().as_str(),
        event.static_config(),
    );
    let stats = open_stats(&node, &settings).unwrap();
    check_pubsub(
        &all,
        "matcher_stats",
        stats.name().as_str(),
        stats.static_config(),
    );
    let (data, event) = open_decision(&node, &settings).unwrap();
    check_pubsub(&all, "decision", data.name().as_str(), data.static_config());
    check_event(
        &all,
        "decision_event",
        event.name().as_str(),
        event.static_config(),
    );
    let requests = open_request_event(&node, &settings).unwrap();
    check_event(
        &all,
        "request_event",
        requests.name().as_str(),
        requests.static_config(),
    );
    let answers = open_answer_event(&node, &settings).unwrap();
    check_event(
        &all,
        "answer_event",
        answers.name().as_str(),
        answers.static_config(),
    );
    checked += 7;

    let reference = open_reference(&node, &settings).unwrap();
    let s = spec(&all, "reference");
    assert_eq!(s.name, reference.name().as_str());
    let Pattern::RequestResponse {
        request,
        response,
        qos,
        request_event,
        response_event,
    } = &s.pattern
    else {
        panic!("reference is not request-response");
    };
    let config = reference.static_config();
    assert_eq!(config.max_clients(), qos.max_clients);
    assert_eq!(config.max_servers(), qos.max_servers);
    assert_eq!(
        config.max_active_requests_per_client(),
        qos.max_active_requests_per_client
    );
    assert_eq!(
        config.max_response_buffer_size(),
        qos.max_response_buffer_size
    );
    assert_eq!(
        config.has_safe_overflow_for_requests(),
        qos.enable_safe_overflow_for_requests
    );
    assert_eq!(
        config.has_safe_overflow_for_responses(),
        qos.enable_safe_overflow_for_responses
    );
    assert_type(
        "request",
        &config.request_message_type_details().payload,
        request,
    );
    assert_type(
        "response",
        &config.response_message_type_details().payload,
        response,
    );
    assert_eq!(request_event, requests.name().as_str());
    assert_eq!(response_event, answers.name().as_str());
    checked += 1;

    assert_eq!(checked, all.len(), "a catalogued service was not opened");
}

#[test]
fn names_follow_the_namespace() {
    let (_dir, settings) = isolated();
    for s in catalogue(&settings) {
        assert!(s.name.starts_with("cat/"), "{}", s.name);
    }
    let roles: std::collections::HashSet<_> = catalogue(&settings).iter().map(|s| s.role).collect();
    assert_eq!(roles.len(), catalogue(&settings).len(), "roles are unique");
}
