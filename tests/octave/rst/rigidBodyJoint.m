% MATLAB Robotics System Toolbox's rigidBodyJoint as MathWorks documents it (a handle object),
% written for urdf2dh's tests: TYPE 'revolute', 'prismatic' or 'fixed'; PositionLimits,
% HomePosition;
% setFixedTransform(joint, T) sets JointToParentTransform = T; setFixedTransform(joint,
% [a alpha d theta], "dh") sets ChildToJointTransform = Rz(theta) Tz(d) Tx(a) Rx(alpha), and
% "mdh" sets JointToParentTransform = Rx(alpha) Tx(a) Rz(theta) Tz(d); theta is ignored for
% revolute joints, d for prismatic ones (the joint variable takes their place).
classdef rigidBodyJoint < handle
  properties
    Name; Type; PositionLimits = []; HomePosition = 0;
    JointToParentTransform = eye(4); ChildToJointTransform = eye(4);
  end
  methods
    function j = rigidBodyJoint(name, type)
      j.Name = name; j.Type = type;
    end
    function setFixedTransform(j, T, convention)
      if nargin < 3
        j.JointToParentTransform = T; j.ChildToJointTransform = eye(4); return;
      end
      a = T(1); alpha = T(2); d = T(3); theta = T(4);
      if strcmp(j.Type, 'revolute'), theta = 0; elseif strcmp(j.Type, 'prismatic'), d = 0; end
      ct = cos(theta); st = sin(theta); ca = cos(alpha); sa = sin(alpha);
      Rz = [ct -st 0 0; st ct 0 0; 0 0 1 0; 0 0 0 1];
      Rx = [1 0 0 0; 0 ca -sa 0; 0 sa ca 0; 0 0 0 1];
      Tz = [1 0 0 0; 0 1 0 0; 0 0 1 d; 0 0 0 1];
      Tx = [1 0 0 a; 0 1 0 0; 0 0 1 0; 0 0 0 1];
      switch convention
        case 'dh', j.JointToParentTransform = eye(4); j.ChildToJointTransform = Rz * Tz * Tx * Rx;
        case 'mdh', j.JointToParentTransform = Rx * Tx * Rz * Tz; j.ChildToJointTransform = eye(4);
        otherwise, error('setFixedTransform: convention %s', convention);
      end
    end
    function T = motion(j, q)
      switch j.Type
        case 'revolute', T = [cos(q) -sin(q) 0 0; sin(q) cos(q) 0 0; 0 0 1 0; 0 0 0 1];
        case 'prismatic', T = [1 0 0 0; 0 1 0 0; 0 0 1 q; 0 0 0 1];
        otherwise, T = eye(4);
      end
    end
  end
end
