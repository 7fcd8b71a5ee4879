window.VREF_LAYOUT = {
  configById: {
    "3D!vref": {
      cameraState: { distance: 2.6, perspective: true, phi: 50, target: [0, 0, 0], targetOffset: [0.95, 0.05, -0.1],
        targetOrientation: [0, 0, 0, 1], thetaOffset: 215, fovy: 45, near: 0.01, far: 5000 },
      followMode: "follow-pose", followTf: "world",
      scene: { enableStats: false, labelScaleFactor: 1, transforms: { showLabel: false, axisScale: 0.4, lineWidth: 1 } },
      transforms: {},
      topics: { "/vref/scene": { visible: true } },
      layers: { grid: { visible: true, frameId: "world", layerId: "foxglove.Grid", size: 4, divisions: 20,
        lineWidth: 1, color: "#248eff80", position: [0, 0, -0.6], rotation: [0, 0, 0], order: 1, label: "Grid", instanceId: "grid" } },
      publish: { type: "point", poseTopic: "/move_base_simple/goal", pointTopic: "/clicked_point", poseEstimateTopic: "/initialpose",
        poseEstimateXDeviation: 0.5, poseEstimateYDeviation: 0.5, poseEstimateThetaDeviation: 0.26179939 },
      imageMode: {},
    },
    "RawMessages!answer": { topicPath: "/vref/answer", diffTopicPath: "", diffMethod: "custom", diffEnabled: false, showFullMessageForDiff: false },
  },
  globalVariables: {},
  userNodes: {},
  playbackConfig: { speed: 1 },
  layout: { first: "3D!vref", second: "RawMessages!answer", direction: "row", splitPercentage: 70 },
};
