% MATLAB's rigidBodyTree as documented (a handle object), for urdf2dh's tests:
% rigidBodyTree("DataFormat", "row"); BaseName; addBody(robot, body, parentName) adds a copy
% of the body's joint; getTransform(robot, q, bodyName) is the body's pose in the base:
% the product along the path of JointToParentTransform * J(q) * ChildToJointTransform, with q
% (a row) giving the non-fixed joints' positions in the order their bodies were added.
classdef rigidBodyTree < handle
  properties
    BaseName = 'base'; Bodies = {}; DataFormat = 'struct';
  end
  methods
    function r = rigidBodyTree(varargin)
      for i = 1:2:numel(varargin)
        r.(varargin{i}) = varargin{i + 1};
      end
    end
    function addBody(r, body, parent)
      names = cellfun(@(b) b.Name, r.Bodies, 'UniformOutput', false);
      if any(strcmp(names, body.Name)) || strcmp(body.Name, r.BaseName)
        error('addBody: duplicate body name %s', body.Name);
      end
      if ~strcmp(parent, r.BaseName) && ~any(strcmp(names, parent))
        error('addBody: no body %s', parent);
      end
      j = body.Joint;
      copy = rigidBodyJoint(j.Name, j.Type);
      copy.PositionLimits = j.PositionLimits;
      copy.JointToParentTransform = j.JointToParentTransform;
      copy.ChildToJointTransform = j.ChildToJointTransform;
      b = rigidBody(body.Name); b.Joint = copy; b.Parent = parent;
      r.Bodies{end + 1} = b;
    end
    function T = getTransform(r, q, name)
      names = cellfun(@(b) b.Name, r.Bodies, 'UniformOutput', false);
      moving = cellfun(@(b) ~strcmp(b.Joint.Type, 'fixed'), r.Bodies);
      index = cumsum(moving);
      T = eye(4);
      while ~strcmp(name, r.BaseName)
        k = find(strcmp(names, name));
        b = r.Bodies{k}; j = b.Joint;
        if moving(k), J = j.motion(q(index(k))); else, J = eye(4); end
        T = j.JointToParentTransform * J * j.ChildToJointTransform * T;
        name = b.Parent;
      end
    end
  end
end
