% MATLAB's rigidBody (a handle object) as documented: a Name and a Joint. For urdf2dh's tests.
classdef rigidBody < handle
  properties
    Name; Joint; Parent = '';
  end
  methods
    function b = rigidBody(name)
      b.Name = name; b.Joint = rigidBodyJoint([name '_jnt'], 'fixed');
    end
  end
end
